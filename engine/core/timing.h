// Wall-clock timing for the figures the tools print (--timings, bench, the preview's panel).
// Tests: none of its own (one line of <chrono>).
#pragma once

#include <chrono>

namespace metamer {

using Clock = std::chrono::steady_clock;

// Milliseconds from `start` to now.
inline double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace metamer
