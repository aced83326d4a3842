#include "reference/lobe_table.h"

#include "core/cache_folder.h"
#include "io/atomic_file.h"
#include "reference/lobe_integrals.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <numbers>
#include <system_error>
#include <thread>

// The shared lookup, compiled as C++ in double on the float data.
namespace metamer::lobe_lookup {
using namespace glm;
#define LT_FLOAT double
#define LT_VEC2 glm::dvec2
#define LT_VEC3 glm::dvec3
#define LT_VEC4 glm::dvec4
#define LOBE_DATA_PARAM const glm::vec4 *lobeData,
#define LOBE_FETCH(i) glm::dvec4(lobeData[(i)])
#include "lobe_lookup.h"
}  // namespace metamer::lobe_lookup

namespace metamer {

namespace {

constexpr double kPi = std::numbers::pi;
// The share of the lobe the early-out may leave on the wrong side (shaders/lobe_lookup.h).
constexpr double kConeTail = 1e-7;
// The quadrature's tolerance for each row of the table, relative to the lobe.
constexpr double kRowTolerance = 1e-8;
// Bumped whenever what a table holds changes (its layout, the builder's method): old files are
// then ignored.
constexpr uint32_t kTableVersion = 2;
constexpr char kMagic[8] = {'M', 'T', 'M', 'R', 'L', 'O', 'B', 'E'};

// The view elevation θe at x1 (the inverse of lobeX1).
double thetaEAt(double x1, double gloss) {
    const double k = LOBE_X1_WARP * std::sqrt(gloss + 1.0);
    return std::expm1(x1 * std::log1p(k * 0.5 * kPi)) / k;
}

// Runs task(0 … count − 1) on `threads` threads.
template <class Task>
void parallelFor(int count, int threads, const Task& task) {
    std::atomic<int> next{0};
    auto work = [&] {
        for (int i; (i = next++) < count;) task(i);
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& thread : pool) thread.join();
}

}  // namespace

LobeTable buildLobeTable(double gloss, int threads) {
    if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    LobeTable table;
    table.gloss = gloss;
    table.data.assign(LOBE_TABLE_VEC4, glm::vec4(0.0f));

    // The moments at the nodes, and the cone of each interval: the widest of five points across
    // it (its ends and three inside), widened by 5 % (the cone varies slowly and smoothly with θe).
    constexpr int kConeSamples = 4;
    const int samples = (LOBE_MOMENT_NODES - 1) * kConeSamples + 1;
    std::vector<LobeMoments> moments(samples);
    parallelFor(samples, threads, [&](int i) {
        moments[i] = lobeMoments(thetaEAt(double(i) / (samples - 1), gloss), gloss, kConeTail);
    });
    for (int i = 0; i < LOBE_MOMENT_NODES; ++i) {
        const LobeMoments& m = moments[i * kConeSamples];
        table.data[i] = glm::vec4(m.gamma, m.sigma1, m.sigma2, std::log(m.unoccluded));
    }
    for (int i = 0; i + 1 < LOBE_MOMENT_NODES; ++i) {
        double widest = 0.0;
        for (int k = 0; k <= kConeSamples; ++k) widest = std::max(widest, moments[i * kConeSamples + k].coneHalfAngle);
        widest *= 1.05;
        table.data[LOBE_CONES_OFFSET + i].x = widest < 0.5 * kPi ? static_cast<float>(std::sin(widest)) : LOBE_NO_CONE;
    }

    // The rows (x1, β_w) for β_w ≤ π/2; each gives its mirror too: the hemisphere −u is (π − β_w,
    // −x2), and I(−u) = I_unoccluded − I(u).
    constexpr int half = (LOBE_BETA_NODES - 1) / 2;
    std::vector<double> f(size_t(LOBE_X1_NODES) * LOBE_BETA_NODES * LOBE_X2_NODES);
    auto at = [&](int i1, int ib, int k) -> double& { return f[(size_t(i1) * LOBE_BETA_NODES + ib) * LOBE_X2_NODES + k]; };
    parallelFor(LOBE_X1_NODES * (half + 1), threads, [&](int task) {
        const int i1 = task / (half + 1), ib = task % (half + 1);
        const double x1 = double(i1) / (LOBE_X1_NODES - 1), thetaE = thetaEAt(x1, gloss);
        // The moments as the lookup interpolates them, so that the rows' coordinates are the lookup's.
        const double xm = x1 * (LOBE_MOMENT_NODES - 1);
        const int m0 = lobe_lookup::lobeStencil(xm, LOBE_MOMENT_NODES);
        const glm::dvec4 w = lobe_lookup::lobeCubicWeights(xm - m0);
        glm::dvec4 m(0.0);
        for (int k = 0; k < 4; ++k) m += w[k] * glm::dvec4(table.data[m0 + k]);
        const double gamma = m.x, sigma1 = m.y, sigma2 = m.z;
        const double betaW = kPi * ib / (LOBE_BETA_NODES - 1);
        const double beta = std::atan2(std::sin(betaW) / sigma2, std::cos(betaW) / sigma1);
        const double spread = std::hypot(sigma1 * std::cos(beta), sigma2 * std::sin(beta));
        std::vector<double> epsilons(LOBE_X2_NODES);
        for (int k = 0; k < LOBE_X2_NODES; ++k) {
            const double x2 = -1.0 + 2.0 * k / (LOBE_X2_NODES - 1);
            epsilons[k] = std::fabs(x2) == 1.0 ? x2 * 0.5 * kPi : std::atan(LOBE_X2_SCALE * std::tan(0.5 * kPi * x2) * spread);
        }
        const HemisphereFractions row = hemisphereFractions(thetaE, gloss, gamma, sigma1, sigma2, beta, epsilons, kRowTolerance);
        for (int k = 0; k < LOBE_X2_NODES; ++k) {
            at(i1, ib, k) = row.fractions[k];
            if (ib < half) at(i1, LOBE_BETA_NODES - 1 - ib, LOBE_X2_NODES - 1 - k) = 1.0 - row.fractions[k];
        }
    });
    // Each x2 interval j holds the four values of its cubic.
    for (int i1 = 0; i1 < LOBE_X1_NODES; ++i1)
        for (int ib = 0; ib < LOBE_BETA_NODES; ++ib)
            for (int j = 0; j + 1 < LOBE_X2_NODES; ++j) {
                const int j0 = std::clamp(j - 1, 0, LOBE_X2_NODES - 4);
                table.data[LOBE_VALUES_OFFSET + (i1 * LOBE_BETA_NODES + ib) * (LOBE_X2_NODES - 1) + j] =
                    glm::vec4(at(i1, ib, j0), at(i1, ib, j0 + 1), at(i1, ib, j0 + 2), at(i1, ib, j0 + 3));
            }
    return table;
}

glm::dvec2 lobeIntegrals(const LobeTable& table, const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& u) {
    return lobe_lookup::lobeIntegrals(table.data.data(), 0, table.gloss, n, v, u);
}

std::filesystem::path lobeCacheFolder() { return cacheFolder("METAMER_LOBE_CACHE"); }

std::string lobeCacheFileName(double gloss) {
    char name[64];
    std::snprintf(name, sizeof name, "lobe-v%u-%016llx.bin", kTableVersion,
                  static_cast<unsigned long long>(std::bit_cast<uint64_t>(gloss)));
    return name;
}

namespace {

struct FileHeader {
    char magic[8];
    uint32_t version, layout[5];
    double gloss;
};

FileHeader headerFor(double gloss) {
    FileHeader h{};
    std::memcpy(h.magic, kMagic, sizeof kMagic);
    h.version = kTableVersion;
    const uint32_t layout[5] = {LOBE_MOMENT_NODES, LOBE_X1_NODES, LOBE_BETA_NODES, LOBE_X2_NODES, LOBE_TABLE_VEC4};
    std::memcpy(h.layout, layout, sizeof layout);
    h.gloss = gloss;
    return h;
}

}  // namespace

std::shared_ptr<LobeTable> readLobeTable(const std::filesystem::path& file, double gloss) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) return nullptr;
    const FileHeader expected = headerFor(gloss);
    const size_t bytes = LOBE_TABLE_VEC4 * sizeof(glm::vec4);
    if (std::filesystem::file_size(file, ec) != sizeof expected + bytes || ec) return nullptr;
    std::ifstream in(file, std::ios::binary);
    FileHeader header{};
    in.read(reinterpret_cast<char*>(&header), sizeof header);
    if (!in || std::memcmp(&header, &expected, sizeof header) != 0) return nullptr;
    auto table = std::make_shared<LobeTable>();
    table->gloss = gloss;
    table->data.resize(LOBE_TABLE_VEC4);
    in.read(reinterpret_cast<char*>(table->data.data()), static_cast<std::streamsize>(bytes));
    if (!in) return nullptr;
    for (const glm::vec4& x : table->data)
        if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z) || !std::isfinite(x.w)) return nullptr;
    return table;
}

void writeLobeTable(const std::filesystem::path& file, const LobeTable& table) {
    const FileHeader header = headerFor(table.gloss);
    std::string bytes(reinterpret_cast<const char*>(&header), sizeof header);
    bytes.append(reinterpret_cast<const char*>(table.data.data()), table.data.size() * sizeof(glm::vec4));
    writeFileAtomically(file, bytes);
}

std::shared_ptr<const LobeTable> lobeTableFor(double gloss) {
    static std::mutex mutex;
    static std::map<uint64_t, std::shared_ptr<const LobeTable>> tables;
    const std::lock_guard lock(mutex);
    auto& slot = tables[std::bit_cast<uint64_t>(gloss)];
    if (slot) return slot;
    const std::filesystem::path folder = lobeCacheFolder();
    const std::filesystem::path file = folder.empty() ? std::filesystem::path() : folder / lobeCacheFileName(gloss);
    if (!file.empty())
        if (auto cached = readLobeTable(file, gloss)) return slot = std::move(cached);
    auto built = std::make_shared<LobeTable>(buildLobeTable(gloss));
    if (!file.empty()) {
        // The cache saves time; failing to write it is not an error of the render.
        std::error_code ec;
        std::filesystem::create_directories(folder, ec);
        try {
            writeLobeTable(file, *built);
        } catch (const std::exception&) {
        }
    }
    return slot = std::move(built);
}

}  // namespace metamer
