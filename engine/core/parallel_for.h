// f(i) for every i in [0, n), split into contiguous blocks over threads: the loop every per-pixel
// pass of the sensor and the image processor runs (each i independent, so any split gives the
// same result). Tests: engine/core/parallel_for_test.cpp.
#pragma once

#include "core/cpu_count.h"

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace metamer {

// On `threads` threads (0: usableCpuCount()), but no more than one per `minPerThread` indices (a
// thread's start costs more than a few thousand cheap iterations) and at most 256.
template <typename F>
void parallelFor(size_t n, int threads, size_t minPerThread, F&& f) {
    size_t t = threads > 0 ? size_t(threads) : size_t(usableCpuCount());
    t = std::clamp<size_t>(std::min(t, n / std::max<size_t>(minPerThread, 1)), 1, 256);
    auto block = [&](size_t k) {
        for (size_t i = n * k / t; i < n * (k + 1) / t; ++i) f(i);
    };
    std::vector<std::thread> pool;
    for (size_t k = 1; k < t; ++k) pool.emplace_back(block, k);
    block(0);
    for (std::thread& th : pool) th.join();
}

}  // namespace metamer
