#include "radiosity/product.h"

#include "core/cpu_count.h"

#include <algorithm>
#include <thread>
#include <vector>

namespace metamer::radiosity {

Eigen::MatrixXd timesOnEveryCore(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    Eigen::MatrixXd out(a.rows(), b.cols());
    // Below a few million multiply-adds a thread costs more than it saves.
    const double work = double(a.rows()) * double(a.cols()) * double(b.cols());
    const Eigen::Index threads = std::min<Eigen::Index>(work < 4e6 ? 1 : usableCpuCount(), b.cols());
    if (threads <= 1) {
        out.noalias() = a * b;
        return out;
    }
    auto part = [&](Eigen::Index t) {
        const Eigen::Index first = b.cols() * t / threads, last = b.cols() * (t + 1) / threads;
        out.middleCols(first, last - first).noalias() = a * b.middleCols(first, last - first);
    };
    std::vector<std::thread> pool;
    for (Eigen::Index t = 1; t < threads; ++t) pool.emplace_back(part, t);
    part(0);
    for (std::thread& t : pool) t.join();
    return out;
}

}  // namespace metamer::radiosity
