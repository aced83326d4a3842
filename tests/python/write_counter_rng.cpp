// Writes what engine/sensor's counter-based generator and Poisson sampler produce, for
// tests/python/check_counter_rng.py to compare with numpy's Philox and scipy's Poisson pmf:
// PREFIX_words.csv — key, counter and the first 12 words of a few streams; PREFIX_poisson.csv — the
// histogram of 10⁶ counts (one stream per sample, as pixels draw them) at each of several means.
// Usage: write_counter_rng PREFIX
#include "sensor/poisson.h"

#include <cstdio>
#include <map>
#include <string>

int main(int argc, char** argv) {
    using namespace metamer;
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s PREFIX\n", argv[0]);
        return 2;
    }
    const std::string words = std::string(argv[1]) + "_words.csv", counts = std::string(argv[1]) + "_poisson.csv";
    std::FILE* f = std::fopen(words.c_str(), "w");
    if (!f) {
        std::perror(words.c_str());
        return 1;
    }
    std::fprintf(f, "k0,k1,c0,c1,c2,index,word\n");
    const PhiloxKey keys[] = {{1, 0}, {0x0123456789abcdefull, 42}, {~0ull, ~0ull}};
    const PhiloxCounter starts[] = {{1, 0, 0, 0}, {12345, 7, 99, 0}, {~0ull, ~0ull, ~0ull, 0}};
    for (const PhiloxKey& k : keys)
        for (const PhiloxCounter& c : starts) {
            CounterStream s(k, c[0], c[1], c[2]);
            for (int i = 0; i < 12; ++i)
                std::fprintf(f, "%llu,%llu,%llu,%llu,%llu,%d,%llu\n", (unsigned long long)k[0], (unsigned long long)k[1],
                             (unsigned long long)c[0], (unsigned long long)c[1], (unsigned long long)c[2], i,
                             (unsigned long long)s.next());
        }
    if (std::fclose(f) != 0) return 1;
    std::FILE* g = std::fopen(counts.c_str(), "w");
    if (!g) {
        std::perror(counts.c_str());
        return 1;
    }
    std::fprintf(g, "mean,k,count\n");
    for (double mean : {0.5, 3.0, 9.99, 10.0, 30.0, 1000.0}) {
        std::map<uint64_t, long> histogram;
        for (uint64_t pixel = 0; pixel < 1000000; ++pixel) {
            CounterStream s({2026, 12}, pixel, 0, 0);
            ++histogram[poisson(mean, s)];
        }
        for (const auto& [k, n] : histogram) std::fprintf(g, "%.17g,%llu,%ld\n", mean, (unsigned long long)k, n);
    }
    return std::fclose(g) == 0 ? 0 : 1;
}
