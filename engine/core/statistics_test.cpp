// core/statistics.h by known answers.
#include "core/statistics.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace metamer;

TEST(Statistics, MedianOfOddAndEvenCounts) {
    EXPECT_EQ(median({3, 1, 2}), 2.0);
    EXPECT_EQ(median({4, 1, 3, 2}), 2.5);
    EXPECT_TRUE(std::isnan(median({})));
}

TEST(Statistics, NearestRankPercentile) {
    std::vector<double> v;
    for (int i = 1; i <= 200; ++i) v.push_back(i);
    EXPECT_EQ(percentile(v, 0.99), 198.0);  // ⌈0.99 · 200⌉ = 198
    EXPECT_EQ(percentile(v, 0.95), 190.0);
    EXPECT_EQ(percentile(v, 0.0), 1.0);
    EXPECT_EQ(percentile(v, 1.0), 200.0);
    EXPECT_EQ(percentile({7}, 0.5), 7.0);
    EXPECT_TRUE(std::isnan(percentile({}, 0.5)));
}
