// Exact Poisson variates for shot noise (issue 29): a count k with P(k) = μᵏe^(−μ)/k!, drawn from a
// CounterStream, so the same (key, counter) gives the same count anywhere. Exact in the sense of
// the methods, not an approximation by a normal law: inversion by sequential search for μ < 10;
// Hörmann's transformed rejection with squeeze (PTRS; W. Hörmann, "The transformed rejection method
// for generating Poisson random variables", Insurance: Mathematics and Economics 12, 1993) for
// μ ≥ 10, whose acceptance test is the Poisson probability itself.
// Tests: sensor/poisson_test.cpp, tests/python/check_counter_rng.py (χ² against scipy's pmf).
#pragma once

#include "sensor/counter_rng.h"

#include <cstdint>

namespace metamer {

// The largest mean poisson() takes (a full well is 10⁵–10⁶ electrons; beyond 10¹² the acceptance
// test's log k! loses the digits that decide it).
constexpr double kMaxPoissonMean = 1e12;

// A Poisson count of mean μ (0 ≤ μ ≤ kMaxPoissonMean; μ = 0 gives 0 and draws nothing).
uint64_t poisson(double mean, CounterStream& stream);

}  // namespace metamer
