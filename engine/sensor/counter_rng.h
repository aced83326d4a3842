// Counter-based random numbers for the simulated sensor (issue 29): Philox4x64-10 (Salmon, Moraes,
// Dror & Shaw, "Parallel random numbers: as easy as 1, 2, 3", SC 2011). A block of four 64-bit
// words is a pure function of a 256-bit counter and a 128-bit key, so a pixel's noise depends only
// on (seed, frame, pixel, channel, draw) — never on strips, threads, order or machine.
// numpy.random.Philox is the same generator (its stream starts at counter + 1), the independent
// oracle of tests/python/check_counter_rng.py.
// Tests: sensor/counter_rng_test.cpp, tests/python/check_counter_rng.py.
#pragma once

#include <array>
#include <cstdint>

namespace metamer {

using PhiloxCounter = std::array<uint64_t, 4>;
using PhiloxKey = std::array<uint64_t, 2>;

// Ten rounds of Philox4x64 on `counter` under `key`.
constexpr PhiloxCounter philox4x64(PhiloxCounter x, PhiloxKey k) {
    constexpr uint64_t kM0 = 0xD2E7470EE14C6C93ull, kM1 = 0xCA5A826395121157ull;  // multipliers
    constexpr uint64_t kW0 = 0x9E3779B97F4A7C15ull, kW1 = 0xBB67AE8584CAA73Bull;  // Weyl key steps
    for (int round = 0; round < 10; ++round) {
        const unsigned __int128 p0 = static_cast<unsigned __int128>(kM0) * x[0];
        const unsigned __int128 p1 = static_cast<unsigned __int128>(kM1) * x[2];
        const uint64_t hi0 = uint64_t(p0 >> 64), lo0 = uint64_t(p0), hi1 = uint64_t(p1 >> 64), lo1 = uint64_t(p1);
        x = {hi1 ^ x[1] ^ k[0], lo1, hi0 ^ x[3] ^ k[1], lo0};
        k[0] += kW0;
        k[1] += kW1;
    }
    return x;
}

// A uniform double in (0, 1) from 64 random bits: the top 52, offset by half a step, so that neither
// 0 nor 1 can come out (log(u) and 1/u stay finite): 2⁻⁵³ … 1 − 2⁻⁵³, all exact in double (53 bits
// and half a step would round the largest to 1).
constexpr double uniformOpen01(uint64_t bits) { return (double(bits >> 12) + 0.5) * 0x1.0p-52; }

// The words of one stream: the blocks at counters {c0, c1, c2, 1}, {c0, c1, c2, 2}, … under `key`,
// four words per block, in order. A sampler that needs an unknown number of draws (rejection)
// takes them from its own stream, so every pixel's draws are its own.
class CounterStream {
public:
    constexpr CounterStream(PhiloxKey key, uint64_t c0, uint64_t c1, uint64_t c2) : key_(key), counter_{c0, c1, c2, 0} {}
    constexpr uint64_t next() {
        if (used_ == 4) {
            ++counter_[3];
            block_ = philox4x64(counter_, key_);
            used_ = 0;
        }
        ++drawn_;
        return block_[used_++];
    }
    constexpr double uniform() { return uniformOpen01(next()); }
    // How many words this stream has handed out (tests, and the draws a sample cost).
    constexpr uint64_t drawn() const { return drawn_; }

private:
    PhiloxKey key_;
    PhiloxCounter counter_;
    PhiloxCounter block_{};
    int used_ = 4;
    uint64_t drawn_ = 0;
};

}  // namespace metamer
