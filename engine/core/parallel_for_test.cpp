#include "core/parallel_for.h"

#include <gtest/gtest.h>

#include <atomic>

using namespace metamer;

TEST(ParallelFor, EveryIndexRunsOnceWhateverTheThreadCount) {
    for (int threads : {0, 1, 2, 3, 7, 300})
        for (size_t n : {size_t(0), size_t(1), size_t(5), size_t(1000), size_t(100003)}) {
            std::vector<std::atomic<int>> seen(n);
            parallelFor(n, threads, 10, [&](size_t i) { seen[i].fetch_add(1); });
            for (size_t i = 0; i < n; ++i) ASSERT_EQ(seen[i].load(), 1) << threads << " threads, n " << n << ", i " << i;
        }
}
