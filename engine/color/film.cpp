#include "color/film.h"
#include "color/cie_xyz.h"
#include "core/file_reads.h"
#include "core/json.h"
#include "spectral/resampling.h"

#include "spectral/csv.h"
#include "spectral/spectrum.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

namespace fs = std::filesystem;

namespace metamer {

namespace {

using Json = nlohmann::ordered_json;

// The description file spectra/film/<name>.json: which library tables hold the film's spectra,
// the light it is balanced for, and one characteristic curve per layer.
struct FilmDescription {
    fs::path path;
    std::string sensitivity, dyeDensity, baseDensity, lamp, balanceIlluminant;
    std::string dyeNames[3];
    FilmCurve curves[3];
};

const char* const kLayerChannels[3] = {"blue", "green", "red"};

std::string requireString(const Json& j, const char* key, const Where& where) {
    if (!j.contains(key)) failInput(where.child(key), "missing (a library name such as \"film/reversal_lamp\")");
    if (!j[key].is_string()) failInput(where.child(key), "expected a string");
    return j[key].get<std::string>();
}

double requireNumber(const Json& j, const char* key, const Where& where) {
    if (!j.contains(key)) failInput(where.child(key), "missing number");
    if (!j[key].is_number()) failInput(where.child(key), "expected a number");
    double v = j[key].get<double>();
    if (!std::isfinite(v)) failInput(where.child(key), "must be finite");
    return v;
}

fs::path descriptionPath(const SpectrumLibrary& library, const std::string& name) {
    return library.root() / "film" / (name + ".json");
}

FilmDescription readDescription(const std::string& name, const SpectrumLibrary& library, const Where& where) {
    FilmDescription d;
    d.path = descriptionPath(library, name);
    noteFileRead(d.path);
    std::error_code ec;
    if (!fs::exists(d.path, ec)) {
        std::string s = closestMatch(name, filmNames(library));
        if (!s.empty()) failInput(where, "no film '{}'; did you mean '{}'?", name, s);
        failInput(where, "no film '{}' ({} not found)", name, d.path.string());
    }
    const Where file{d.path.string()};
    // The one JSON reader (core/json.h): a regular file of sane size, depth-capped, duplicate keys refused.
    const Json j = parseJson(readWholeFile(d.path, file, "film description"), d.path.string());
    if (!j.is_object()) failInput(file, "expected a JSON object");
    d.sensitivity = requireString(j, "sensitivity", file);
    d.dyeDensity = requireString(j, "dye_density", file);
    d.baseDensity = requireString(j, "base_density", file);
    d.lamp = requireString(j, "lamp", file);
    d.balanceIlluminant = requireString(j, "balance_illuminant", file);
    if (!j.contains("layers") || !j["layers"].is_array() || j["layers"].size() != 3)
        failInput(file.child("layers"), "expected an array of 3 layers (blue, green, red)");
    for (int i = 0; i < 3; ++i) {
        const Json& l = j["layers"][i];
        Where lw = file.child("layers").index(i);
        if (!l.is_object()) failInput(lw, "expected an object");
        std::string channel = requireString(l, "channel", lw);
        if (channel != kLayerChannels[i])
            failInput(lw.child("channel"), "layer {} must be '{}' (layers are blue, green, red), got '{}'", i,
                      kLayerChannels[i], channel);
        d.dyeNames[i] = requireString(l, "dye", lw);
        FilmCurve& c = d.curves[i];
        c.dMin = requireNumber(l, "d_min", lw);
        c.dMax = requireNumber(l, "d_max", lw);
        c.logH0 = requireNumber(l, "log_h0", lw);
        c.gamma = requireNumber(l, "gamma", lw);
        c.toe = requireNumber(l, "toe", lw);
        if (c.dMin < 0) failInput(lw.child("d_min"), "must be ≥ 0, got {}", c.dMin);
        if (!(c.dMax > c.dMin)) failInput(lw.child("d_max"), "must exceed d_min ({}), got {}", c.dMin, c.dMax);
        if (!(c.gamma > 0)) failInput(lw.child("gamma"), "must be > 0 (the curve's mid slope is −gamma), got {}", c.gamma);
        if (!(c.toe > 0)) failInput(lw.child("toe"), "must be > 0, got {}", c.toe);
    }
    return d;
}

// A library table with `columns` value columns, each resampled onto the grid (spectral/resampling.h).
std::vector<std::vector<double>> tableOnGrid(const SpectrumLibrary& library, const std::string& name, size_t columns,
                                             const Grid& grid, const Where& where, std::vector<std::string>* header) {
    if (!library.contains(name)) {
        std::string s = library.suggest(name);
        if (!s.empty()) failInput(where, "no table '{}' in the spectra library; did you mean '{}'?", name, s);
        failInput(where, "no table '{}' in the spectra library ({})", name, library.root().string());
    }
    fs::path path = library.root() / (name + ".csv");
    SpectralTable t = readSpectralTable(path, 1);
    if (t.columns.size() != columns)
        failInput(Where{path.string()}, "expected {} value column(s), found {}", columns, t.columns.size());
    if (header) *header = t.columnNames;
    std::vector<std::vector<double>> out;
    for (auto& col : t.columns) {
        Spectrum s;
        s.wavelengths_nm = t.wavelengths_nm;
        s.values = col;
        s.source = name;
        out.push_back(resample(s, grid));
    }
    return out;
}

Detector layersDetector(const FilmDescription& d, const std::string& name, const SpectrumLibrary& library,
                        const Grid& grid, Integration integration) {
    Detector det;
    det.name = "film:" + name;
    det.kind = DetectorKind::Film;
    det.channels = {"blue", "green", "red"};
    det.units = "relative layer exposure (sensitivity peak 1 × W·sr⁻¹·m⁻²·nm⁻¹ × nm)";
    det.source = d.sensitivity;
    det.grid = grid;
    det.integration = integration;
    std::vector<double> q = quadratureWeights(grid, integration);
    det.weights = tableOnGrid(library, d.sensitivity, 3, grid, Where{d.path.string(), "sensitivity"}, nullptr);
    for (auto& w : det.weights)
        for (size_t b = 0; b < w.size(); ++b) w[b] *= q[b];
    return det;
}

// sp(a) − sp(a − c) for c > 0, sp(z) = ln(1 + e^z), without cancellation for large |a|.
double softplusDifference(double a, double c) {
    if (a >= c) return c + std::log1p(std::exp(-a)) - std::log1p(std::exp(c - a));
    if (a <= 0) return std::log1p(std::exp(a)) - std::log1p(std::exp(a - c));
    return a + std::log1p(std::exp(-a)) - std::log1p(std::exp(a - c));
}

}  // namespace

double filmCurveDensity(const FilmCurve& curve, double x) {
    if (std::isnan(x)) return x;
    if (x == -std::numeric_limits<double>::infinity()) return curve.dMax;
    if (x == std::numeric_limits<double>::infinity()) return curve.dMin;
    const double r = curve.dMax - curve.dMin;
    // γ' makes the slope at the middle exactly −gamma: the rounding of toe and shoulder lowers the
    // straight line's slope there by tanh(R/(4·toe)) (≈ 1 for a long curve, but not exactly).
    const double g = curve.gamma / std::tanh(r / (4.0 * curve.toe));
    const double u = g * (curve.logH0 - x) + 0.5 * r;
    return curve.dMin + curve.toe * softplusDifference(u / curve.toe, r / curve.toe);
}

std::vector<std::string> filmNames(const SpectrumLibrary& library) {
    std::vector<std::string> names;
    std::error_code ec;
    fs::path dir = library.root() / "film";
    if (!fs::is_directory(dir, ec)) return names;
    for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator(); it.increment(ec))
        if (it->is_regular_file() && it->path().extension() == ".json") names.push_back(it->path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

Detector makeFilmLayers(const std::string& name, const SpectrumLibrary& library, const Grid& grid,
                        Integration integration, const Where& where) {
    FilmDescription d = readDescription(name, library, where);
    return layersDetector(d, name, library, grid, integration);
}

FilmModel makeFilm(const std::string& name, const SpectrumLibrary& library, const Grid& grid, Integration integration,
                   const std::vector<double>& referenceWhiteRadianceOnGrid, const Where& where) {
    const FilmDescription d = readDescription(name, library, where);
    const Where file{d.path.string()};
    const size_t n = static_cast<size_t>(grid.bands());
    if (referenceWhiteRadianceOnGrid.size() != n)
        failRuntime("film '{}': reference white has {} bands, the grid {} has {}", name,
                    referenceWhiteRadianceOnGrid.size(), grid.str(), n);

    FilmModel m;
    m.name = name;
    m.layers = layersDetector(d, name, library, grid, integration);
    for (int i = 0; i < 3; ++i) m.curves[i] = d.curves[i];
    m.balanceIlluminant = d.balanceIlluminant;
    m.lamp = d.lamp;

    // Dyes: columns matched to the layers by header name when the table has one, else in order.
    std::vector<std::string> header;
    auto dyes = tableOnGrid(library, d.dyeDensity, 3, grid, file.child("dye_density"), &header);
    m.dyeDensity.resize(3);
    for (int i = 0; i < 3; ++i) {
        size_t col = static_cast<size_t>(i);
        if (!header.empty()) {
            auto it = std::find(header.begin(), header.end(), d.dyeNames[i]);
            if (it == header.end())
                failInput(file.child("layers").index(i).child("dye"), "dye '{}' is not a column of {}", d.dyeNames[i],
                          d.dyeDensity);
            col = static_cast<size_t>(it - header.begin());
        }
        m.dyeDensity[i] = dyes[col];
    }
    m.baseDensity = tableOnGrid(library, d.baseDensity, 1, grid, file.child("base_density"), nullptr)[0];

    // Projection: the lamp through the slide, seen by the CIE 1931 observer with the same
    // quadrature as the layers.
    std::vector<double> lamp = resample(library.get(d.lamp, file.child("lamp")), grid);
    Detector cmf = observerDetector("cie1931", kCie1931Observer, library, grid, integration);
    m.projection.assign(3, std::vector<double>(n, 0.0));
    for (int c = 0; c < 3; ++c)
        for (size_t b = 0; b < n; ++b) m.projection[c][b] = lamp[b] * cmf.weights[c][b];
    for (size_t b = 0; b < n; ++b) m.openGateY += m.projection[1][b];
    glm::dvec3 clear(m.curves[0].dMin, m.curves[1].dMin, m.curves[2].dMin);
    m.projectedWhiteY = 1.0;
    m.projectedWhiteY = filmXyzFromDensities(m, clear).y;  // unnormalized Y of the clear film
    if (!(m.projectedWhiteY > 0))
        failInput(file.child("lamp"), "the projected film has no luminance on the grid {} (it must cover visible bands)",
                  grid.str());

    // Exposure: balanced for the balance illuminant, metered on the green layer for the scene.
    std::vector<double> balance = resample(library.get(d.balanceIlluminant, file.child("balance_illuminant")), grid);
    glm::dvec3 hBalance = detectorResponse3(m.layers, balance.data());
    glm::dvec3 hWhite = detectorResponse3(m.layers, referenceWhiteRadianceOnGrid.data());
    for (int i = 0; i < 3; ++i)
        if (!(hBalance[i] > 0))
            failInput(file.child("balance_illuminant"), "{} exposes the {} layer not at all on the grid {}",
                      d.balanceIlluminant, kLayerChannels[i], grid.str());
    if (!(hWhite.y > 0))
        failInput(where, "film '{}': the reference white exposes the green layer not at all on the grid {}", name,
                  grid.str());
    m.exposureOfWhite = hBalance * (hWhite.y / hBalance.y);
    return m;
}

glm::dvec3 filmExposures(const FilmModel& film, const double* radianceBands) {
    return detectorResponse3(film.layers, radianceBands);
}

glm::dvec3 filmDensitiesFromExposures(const FilmModel& film, const glm::dvec3& exposures) {
    glm::dvec3 d;
    for (int i = 0; i < 3; ++i) {
        // No (or negative, from numerical noise) light: the unexposed film, dMax.
        double x = exposures[i] > 0 ? std::log10(exposures[i] / film.exposureOfWhite[i])
                                    : -std::numeric_limits<double>::infinity();
        d[i] = filmCurveDensity(film.curves[i], x);
    }
    return d;
}

glm::dvec3 filmXyzFromDensities(const FilmModel& film, const glm::dvec3& densities) {
    glm::dvec3 xyz(0.0);
    const size_t n = film.baseDensity.size();
    for (size_t b = 0; b < n; ++b) {
        double dl = film.baseDensity[b] + densities[0] * film.dyeDensity[0][b] + densities[1] * film.dyeDensity[1][b] +
                    densities[2] * film.dyeDensity[2][b];
        double t = std::pow(10.0, -dl);
        xyz.x += film.projection[0][b] * t;
        xyz.y += film.projection[1][b] * t;
        xyz.z += film.projection[2][b] * t;
    }
    return xyz / film.projectedWhiteY;
}

glm::dvec3 filmXyz(const FilmModel& film, const double* radianceBands) {
    return filmXyzFromDensities(film, filmDensitiesFromExposures(film, filmExposures(film, radianceBands)));
}

}  // namespace metamer
