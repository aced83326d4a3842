#include "color/delta_e.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>

namespace metamer {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Hue angle in degrees, 0 ≤ h < 360; 0 for a neutral (a' = b' = 0), as the formula requires.
double hueDegrees(double b, double a) {
    if (a == 0.0 && b == 0.0) return 0.0;
    double h = std::atan2(b, a) / kDeg;
    return h < 0.0 ? h + 360.0 : h;
}

}  // namespace

double deltaE76(const glm::dvec3& lab1, const glm::dvec3& lab2) { return glm::length(lab1 - lab2); }

double deltaE2000(const glm::dvec3& lab1, const glm::dvec3& lab2) {
    const double L1 = lab1.x, a1 = lab1.y, b1 = lab1.z;
    const double L2 = lab2.x, a2 = lab2.y, b2 = lab2.z;

    // 1. a' stretches the a* axis for near-neutral colours, where CIELAB's blue-grey hues are
    //    too compressed: G goes from 0.5 (neutral) to 0 (very chromatic).
    const double Cab = 0.5 * (std::hypot(a1, b1) + std::hypot(a2, b2));
    const double Cab7 = std::pow(Cab, 7.0);
    const double G = 0.5 * (1.0 - std::sqrt(Cab7 / (Cab7 + std::pow(25.0, 7.0))));
    const double a1p = (1.0 + G) * a1, a2p = (1.0 + G) * a2;
    const double C1p = std::hypot(a1p, b1), C2p = std::hypot(a2p, b2);
    const double h1p = hueDegrees(b1, a1p), h2p = hueDegrees(b2, a2p);

    // 2. Differences. The hue difference takes the short way round the circle; with a neutral
    //    colour (C' = 0) the hue is undefined and ΔH' is 0.
    const double dLp = L2 - L1;
    const double dCp = C2p - C1p;
    const double C12 = C1p * C2p;
    double dhp = 0.0;
    if (C12 != 0.0) {
        dhp = h2p - h1p;
        if (dhp > 180.0) dhp -= 360.0;
        else if (dhp < -180.0) dhp += 360.0;
    }
    const double dHp = 2.0 * std::sqrt(C12) * std::sin(0.5 * dhp * kDeg);

    // 3. Means. The mean hue is the mid-point of the short arc; Sharma et al. fix the cases of a
    //    neutral (sum of the hues) and of hues exactly 180° apart (the branch below).
    const double Lbar = 0.5 * (L1 + L2);
    const double Cbar = 0.5 * (C1p + C2p);
    double hbar = h1p + h2p;
    if (C12 != 0.0) {
        if (std::abs(h1p - h2p) <= 180.0) hbar *= 0.5;
        else hbar = (hbar < 360.0) ? 0.5 * (hbar + 360.0) : 0.5 * (hbar - 360.0);
    }

    // 4. Weighting functions and the rotation term that tilts the blue ellipses.
    const double T = 1.0 - 0.17 * std::cos((hbar - 30.0) * kDeg) + 0.24 * std::cos(2.0 * hbar * kDeg) +
                     0.32 * std::cos((3.0 * hbar + 6.0) * kDeg) - 0.20 * std::cos((4.0 * hbar - 63.0) * kDeg);
    const double dTheta = 30.0 * std::exp(-std::pow((hbar - 275.0) / 25.0, 2.0));
    const double Cbar7 = std::pow(Cbar, 7.0);
    const double RC = 2.0 * std::sqrt(Cbar7 / (Cbar7 + std::pow(25.0, 7.0)));
    const double Lm50 = (Lbar - 50.0) * (Lbar - 50.0);
    const double SL = 1.0 + 0.015 * Lm50 / std::sqrt(20.0 + Lm50);
    const double SC = 1.0 + 0.045 * Cbar;
    const double SH = 1.0 + 0.015 * Cbar * T;
    const double RT = -std::sin(2.0 * dTheta * kDeg) * RC;

    const double l = dLp / SL, c = dCp / SC, h = dHp / SH;  // kL = kC = kH = 1
    return std::sqrt(l * l + c * c + h * h + RT * c * h);
}

}  // namespace metamer
