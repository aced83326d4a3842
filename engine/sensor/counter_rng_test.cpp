#include "sensor/counter_rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

using namespace metamer;

TEST(CounterRng, PhiloxMatchesNumpysPhiloxStream) {
    // numpy.random.Philox(counter=[5, 0, 0, 0], key=[7, 9]).random_raw(8): numpy increments the
    // counter before each block, so these are the blocks at counters 6 and 7.
    const PhiloxCounter a = philox4x64({6, 0, 0, 0}, {7, 9}), b = philox4x64({7, 0, 0, 0}, {7, 9});
    EXPECT_EQ(a, (PhiloxCounter{0xca3338aabc68b165ull, 0xf59ac89340e9a844ull, 0x31d671c919168ce1ull, 0x26084f673b9c63cdull}));
    EXPECT_EQ(b, (PhiloxCounter{0x63d96c01b2976dd0ull, 0xa27607e2f694d4f6ull, 0xbd4169700af5d066ull, 0xc66f5b8d6b7a23ecull}));
}

TEST(CounterRng, AStreamIsAPureFunctionOfKeyAndCounter) {
    CounterStream s({1, 2}, 10, 20, 30), t({1, 2}, 10, 20, 30), other({1, 2}, 11, 20, 30);
    std::set<uint64_t> seen;
    for (int i = 0; i < 9; ++i) {
        const uint64_t x = s.next();
        EXPECT_EQ(x, t.next());
        EXPECT_NE(x, other.next());
        seen.insert(x);
    }
    EXPECT_EQ(seen.size(), 9u);
    EXPECT_EQ(s.drawn(), 9u);
    // Word 5 is the second block's first: counter {10, 20, 30, 2}.
    CounterStream u({1, 2}, 10, 20, 30);
    for (int i = 0; i < 4; ++i) u.next();
    EXPECT_EQ(u.next(), philox4x64({10, 20, 30, 2}, {1, 2})[0]);
}

TEST(CounterRng, UniformsAreInsideTheOpenInterval) {
    EXPECT_GT(uniformOpen01(0), 0.0);
    EXPECT_LT(uniformOpen01(~0ull), 1.0);
    EXPECT_EQ(uniformOpen01(0), 0x1.0p-53);
    EXPECT_EQ(uniformOpen01(~0ull), 1.0 - 0x1.0p-53);
    CounterStream s({3, 4}, 0, 0, 0);
    double sum = 0.0;
    const int n = 1 << 20;
    for (int i = 0; i < n; ++i) sum += s.uniform();
    EXPECT_NEAR(sum / n, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / n));  // 5σ
}
