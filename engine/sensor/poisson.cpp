#include "sensor/poisson.h"

#include <cmath>

namespace metamer {

namespace {

// Inversion: the smallest k with F(k) ≥ u, summing the pmf up from P(0) = e^(−μ). For μ < 10 the
// terms stay above 4.5·10⁻⁵ at the mode, so no underflow; the search ends within a few dozen steps
// (and at the last representable term if rounding leaves F just below a u near 1).
uint64_t poissonByInversion(double mean, CounterStream& stream) {
    const double u = stream.uniform();
    double p = std::exp(-mean), cumulative = p;
    uint64_t k = 0;
    while (u > cumulative) {
        ++k;
        p *= mean / double(k);
        if (p == 0.0) break;
        cumulative += p;
    }
    return k;
}

// PTRS: a proposal k from a transformed uniform, accepted at once inside the squeeze, else by
// comparing log V·(hat's density) with log P(k).
uint64_t poissonByTransformedRejection(double mean, CounterStream& stream) {
    const double root = std::sqrt(mean), logMean = std::log(mean);
    const double b = 0.931 + 2.53 * root, a = -0.059 + 0.02483 * b;
    const double inverseAlpha = 1.1239 + 1.1328 / (b - 3.4), vr = 0.9277 - 3.6224 / (b - 2.0);
    for (;;) {
        const double u = stream.uniform() - 0.5, v = stream.uniform();
        const double us = 0.5 - std::fabs(u);
        const double k = std::floor((2.0 * a / us + b) * u + mean + 0.43);
        if (us >= 0.07 && v <= vr) return uint64_t(k);
        if (k < 0.0 || (us < 0.013 && v > us)) continue;
        if (std::log(v) + std::log(inverseAlpha) - std::log(a / (us * us) + b) <=
            -mean + k * logMean - std::lgamma(k + 1.0))
            return uint64_t(k);
    }
}

}  // namespace

uint64_t poisson(double mean, CounterStream& stream) {
    if (!(mean > 0.0)) return 0;
    return mean < 10.0 ? poissonByInversion(mean, stream) : poissonByTransformedRejection(mean, stream);
}

}  // namespace metamer
