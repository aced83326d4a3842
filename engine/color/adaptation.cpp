#include "color/adaptation.h"

#include <glm/matrix.hpp>

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

namespace {

// The published tables are printed row by row; glm stores columns, so build from rows here and
// nowhere else.
glm::dmat3 fromRows(const std::array<double, 9>& r) {
    return glm::transpose(glm::dmat3(r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8]));
}

const std::array<std::pair<Adaptation, const char*>, 6> kNames{{
    {Adaptation::None, "none"},
    {Adaptation::VonKriesXyz, "vonkries-xyz"},
    {Adaptation::VonKriesLms, "vonkries"},
    {Adaptation::Bradford, "bradford"},
    {Adaptation::Cat02, "cat02"},
    {Adaptation::Cat16, "cat16"},
}};

}  // namespace

Adaptation parseAdaptation(const std::string& name, const Where& where) {
    std::vector<std::string> choices;
    for (const auto& [a, n] : kNames) {
        if (name == n) return a;
        choices.push_back(n);
    }
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
    std::string suggestion = closestMatch(name, choices);
    if (!suggestion.empty())
        failInput(where, "unknown chromatic adaptation '{}'; did you mean '{}'? (choices: {})", name, suggestion,
                  list);
    failInput(where, "unknown chromatic adaptation '{}' (choices: {})", name, list);
}

std::string adaptationName(Adaptation a) {
    for (const auto& [value, n] : kNames)
        if (value == a) return n;
    return "unknown";
}

glm::dmat3 catConeMatrix(Adaptation a) {
    switch (a) {
        case Adaptation::None:
        case Adaptation::VonKriesXyz:
            return glm::dmat3(1.0);
        case Adaptation::VonKriesLms:
            // Hunt–Pointer–Estévez, rows scaled so that D65 gives L = M = S ≈ 1 (the table in
            // Lindbloom's "Chromatic Adaptation" and colour-science's "Von Kries"). The scaling
            // of the rows cancels in M⁻¹·diag·M; the equal-energy-normalized table of CIECAM97s
            // differs only by it (and by rounding in the 5th digit).
            return fromRows({0.40024, 0.70760, -0.08081,
                             -0.22630, 1.16532, 0.04570,
                             0.0, 0.0, 0.91822});
        case Adaptation::Bradford:
            // Lam (1985), linearized (no blue non-linearity), as in ICC.1 Annex E and Lindbloom.
            return fromRows({0.8951, 0.2664, -0.1614,
                             -0.7502, 1.7135, 0.0367,
                             0.0389, -0.0685, 1.0296});
        case Adaptation::Cat02:
            // CIE 159:2004, M_CAT02.
            return fromRows({0.7328, 0.4296, -0.1624,
                             -0.7036, 1.6975, 0.0061,
                             0.0030, 0.0136, 0.9834});
        case Adaptation::Cat16:
            // Li, Li, Wang, Zu, Luo, Cui, Melgosa, Brill & Pointer, "Comprehensive color solutions:
            // CAM16, CAT16, and CAM16-UCS", Color Res. Appl. 42(6), 2017, M16.
            return fromRows({0.401288, 0.650173, -0.051461,
                             -0.250268, 1.204414, 0.045854,
                             -0.002079, 0.048952, 0.953127});
    }
    return glm::dmat3(1.0);
}

glm::dmat3 adaptationMatrix(Adaptation a, const glm::dvec3& sourceWhite, const glm::dvec3& destinationWhite) {
    if (a == Adaptation::None) return glm::dmat3(1.0);
    const glm::dmat3 m = catConeMatrix(a);
    const glm::dvec3 rhoS = m * sourceWhite;
    const glm::dvec3 rhoD = m * destinationWhite;
    // glm::dmat3(v) would be a scalar matrix; build the diagonal explicitly.
    glm::dmat3 gain(0.0);
    for (int i = 0; i < 3; ++i) gain[i][i] = rhoD[i] / rhoS[i];
    return glm::inverse(m) * gain * m;
}

}  // namespace metamer
