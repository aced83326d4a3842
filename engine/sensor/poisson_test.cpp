#include "sensor/poisson.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace metamer;

namespace {

// n samples of mean μ, each from its own stream (pixel i), as a sensor draws them.
std::vector<uint64_t> samples(double mean, int n, uint64_t seed = 1) {
    std::vector<uint64_t> out(size_t(n), 0);
    for (int i = 0; i < n; ++i) {
        CounterStream s({seed, 0}, uint64_t(i), 0, 0);
        out[size_t(i)] = poisson(mean, s);
    }
    return out;
}

}  // namespace

TEST(Poisson, MeanAndVarianceWithinTheirStatisticalBounds) {
    // For n samples of a Poisson law, the sample mean has standard error √(μ/n) and the sample
    // variance √((μ + 2μ²)/n) (its fourth central moment is μ + 3μ²). 5σ bounds: a correct sampler
    // fails one of these 14 checks about once in 10⁵ runs; the samples are fixed, so it never flakes.
    const int n = 1000000;
    for (double mean : {0.5, 3.0, 9.99, 10.0, 30.0, 1000.0, 1e6}) {
        const std::vector<uint64_t> k = samples(mean, n);
        double sum = 0.0, sq = 0.0;
        for (uint64_t v : k) sum += double(v);
        const double m = sum / n;
        for (uint64_t v : k) sq += (double(v) - m) * (double(v) - m);
        const double var = sq / (n - 1);
        EXPECT_NEAR(m, mean, 5.0 * std::sqrt(mean / n)) << "mean " << mean;
        EXPECT_NEAR(var, mean, 5.0 * std::sqrt((mean + 2.0 * mean * mean) / n)) << "mean " << mean;
    }
}

TEST(Poisson, ZeroMeanGivesZeroAndDrawsNothing) {
    CounterStream s({1, 1}, 0, 0, 0);
    EXPECT_EQ(poisson(0.0, s), 0u);
    EXPECT_EQ(poisson(-1.0, s), 0u);
    EXPECT_EQ(s.drawn(), 0u);
}

TEST(Poisson, TheSameStreamGivesTheSameCounts) {
    EXPECT_EQ(samples(30.0, 1000, 7), samples(30.0, 1000, 7));
    EXPECT_NE(samples(30.0, 1000, 7), samples(30.0, 1000, 8));
}

TEST(Poisson, HugeMeansStayFiniteAndClose) {
    CounterStream s({5, 5}, 0, 0, 0);
    for (int i = 0; i < 100; ++i) {
        const double k = double(poisson(kMaxPoissonMean, s));
        EXPECT_NEAR(k, kMaxPoissonMean, 7.0 * std::sqrt(kMaxPoissonMean));
    }
}
