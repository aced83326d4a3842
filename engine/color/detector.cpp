#include "color/detector.h"
#include "spectral/resampling.h"

#include "color/cie_xyz.h"
#include "spectral/spectrum.h"

namespace metamer {

Integration parseIntegration(const std::string& name, const Where& where) {
    if (name == "riemann") return Integration::Riemann;
    if (name == "trapezoid") return Integration::Trapezoid;
    if (name == "astm-e308") return Integration::AstmE308;
    std::string near = closestMatch(name, {"riemann", "trapezoid", "astm-e308"});
    failInput(where, "unknown integration '{}' (riemann, trapezoid or astm-e308){}", name,
              near.empty() ? "" : fmt::format("; did you mean '{}'?", near));
}

const char* integrationName(Integration integration) {
    switch (integration) {
        case Integration::Riemann: return "riemann";
        case Integration::Trapezoid: return "trapezoid";
        case Integration::AstmE308: return "astm-e308";
    }
    return "?";
}

std::vector<double> quadratureWeights(const Grid& grid, Integration integration) {
    if (integration == Integration::AstmE308)
        failRuntime("ASTM E308 weights depend on the reference white: color/astm_e308.h makes them");
    std::vector<double> q(static_cast<size_t>(grid.bands()), grid.step_nm);
    if (integration == Integration::Trapezoid && q.size() > 1) {
        q.front() *= 0.5;
        q.back() *= 0.5;
    }
    return q;
}

Detector observerDetector(const std::string& spec, const std::string& libraryName, const SpectrumLibrary& library,
                          const Grid& grid, Integration integration) {
    // Reuse the colour-matching-function loader (its resampling and errors), then apply the
    // quadrature weights: cmfs hold plain band averages.
    ColorMatchingFunctions cmfs = loadObserver(library, libraryName, grid);
    std::vector<double> q = quadratureWeights(grid, integration);
    Detector d;
    d.name = spec;
    d.kind = DetectorKind::Observer;
    d.channels = {"X", "Y", "Z"};
    d.units = "W·sr⁻¹·m⁻² (radiometric tristimulus value: ∫ cmf·L dλ, no 683 lm/W)";
    d.source = libraryName;
    d.grid = grid;
    d.integration = integration;
    for (const auto* cmf : {&cmfs.x, &cmfs.y, &cmfs.z}) {
        std::vector<double> w(*cmf);
        for (size_t b = 0; b < w.size(); ++b) w[b] *= q[b];
        d.weights.push_back(std::move(w));
    }
    return d;
}

std::vector<double> detectorResponse(const Detector& detector, const double* bands) {
    std::vector<double> r(detector.weights.size(), 0.0);
    for (size_t c = 0; c < r.size(); ++c) {
        const auto& w = detector.weights[c];
        double sum = 0.0;
        for (size_t b = 0; b < w.size(); ++b) sum += w[b] * bands[b];
        r[c] = sum;
    }
    return r;
}

namespace {
template <typename T>
glm::dvec3 response3(const Detector& detector, const T* bands) {
    if (detector.weights.size() != 3)
        failRuntime("detector '{}' has {} channels, not 3", detector.name, detector.weights.size());
    glm::dvec3 r(0.0);
    for (int c = 0; c < 3; ++c) {
        const auto& w = detector.weights[c];
        double sum = 0.0;
        for (size_t b = 0; b < w.size(); ++b) sum += w[b] * static_cast<double>(bands[b]);
        r[c] = sum;
    }
    return r;
}
}  // namespace

glm::dvec3 detectorResponse3(const Detector& detector, const double* bands) { return response3(detector, bands); }
glm::dvec3 detectorResponse3(const Detector& detector, const float* bands) { return response3(detector, bands); }

}  // namespace metamer
