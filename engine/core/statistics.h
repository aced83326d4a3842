// Order statistics the tools report, one definition each so their figures agree (compare's p95,
// bench's, the quick look's exposure). Tests: core/statistics_test.cpp.
#pragma once

#include <vector>

namespace metamer {

// The median (the mean of the two middle values for an even count); NaN for no values.
double median(std::vector<double> values);

// The nearest-rank percentile, p in [0, 1]: the ⌈p·n⌉-th smallest value (the smallest for p = 0);
// NaN for no values.
double percentile(std::vector<double> values, double p);

}  // namespace metamer
