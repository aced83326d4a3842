#include "color/detector.h"
#include "spectral/resampling.h"

#include "color/cie_xyz.h"
#include "core/file_reads.h"
#include "color/film.h"
#include "spectral/csv.h"
#include "spectral/spectrum.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace fs = std::filesystem;

namespace metamer {

namespace {

constexpr size_t kMaxCsvChannels = 8;  // what the tonemap pass can carry per pixel

constexpr const char* kCameraPrefix = "camera:";
constexpr const char* kFilmPrefix = "film:";
constexpr const char* kCsvPrefix = "csv:";

bool startsWith(const std::string& s, const std::string& prefix) {
    return s.compare(0, prefix.size(), prefix) == 0;
}

// Sensitivity columns of a table, resampled onto the grid and multiplied by the quadrature
// weights: the detector's weights.
std::vector<std::vector<double>> weightsFromTable(const SpectralTable& table, const std::string& source,
                                                  const Grid& grid, const std::vector<double>& q) {
    std::vector<std::vector<double>> w;
    for (const auto& column : table.columns) {
        Spectrum s;
        s.wavelengths_nm = table.wavelengths_nm;
        s.values = column;
        s.source = source;
        std::vector<double> band = resample(s, grid);
        for (size_t b = 0; b < band.size(); ++b) band[b] *= q[b];
        w.push_back(std::move(band));
    }
    return w;
}

Detector observer(const std::string& spec, const std::string& libraryName, const SpectrumLibrary& library,
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

std::vector<std::string> cameraNames(const SpectrumLibrary& library) {
    std::vector<std::string> out;
    for (const auto& n : library.names())
        if (startsWith(n, "cameras/")) out.push_back(n.substr(8));
    return out;
}

Detector camera(const std::string& spec, const std::string& name, const SpectrumLibrary& library, const Grid& grid,
                Integration integration, const Where& where) {
    std::string libraryName = "cameras/" + name;
    fs::path path = library.root() / (libraryName + ".csv");
    SpectralTable table = readSpectralTable(path, 1);
    if (table.columns.size() != 3)
        failInput(Where{path.string()}, "a camera needs 3 value columns (wavelength_nm,r,g,b), found {}",
                  table.columns.size());
    (void)where;
    Detector d;
    d.name = spec;
    d.kind = DetectorKind::Camera;
    d.channels = {"R", "G", "B"};
    d.units = "relative camera signal (sensitivity, peak ≈ 1, × W·sr⁻¹·m⁻²·nm⁻¹ × nm)";
    d.source = libraryName;
    d.grid = grid;
    d.integration = integration;
    // Measured data end where the measurement did (the Sigma set at 400 and 680 nm): the camera is
    // taken as blind outside, documented in spectra/README.md rather than warned about each time.
    d.weights = weightsFromTable(table, libraryName, grid, quadratureWeights(grid, integration));
    return d;
}

Detector customCsv(const std::string& spec, const std::string& pathText, const Grid& grid, Integration integration,
                   const Where& where) {
    if (pathText.empty()) failInput(where, "'{}': expected csv:PATH to a sensitivity table", spec);
    fs::path path = fs::absolute(fs::path(pathText));
    requireRegularFile(path, Where{path.string(), where.key, 0}, "detector sensitivity file");
    SpectralTable table = readSpectralTable(path, 1);
    const Where fileWhere{path.string(), where.key, 0};
    if (table.columns.size() > kMaxCsvChannels)
        failInput(fileWhere, "a detector has 1 to {} channels; this table has {} value columns", kMaxCsvChannels,
                  table.columns.size());
    Spectrum first;
    first.wavelengths_nm = table.wavelengths_nm;
    first.values = table.columns[0];
    CoverageGap gap = coverage(first, grid);
    if (!gap.overlaps)
        failInput(fileWhere, "the sensitivities ({:g}–{:g} nm) lie entirely outside the grid {}", gap.data_lo,
                  gap.data_hi, grid.str());
    if (!gap.covered)
        warn(fileWhere, fmt::format("the sensitivities cover {:g}–{:g} nm but the grid is {}; the detector is "
                                    "taken as blind (0) outside its data",
                                    gap.data_lo, gap.data_hi, grid.str()));
    Detector d;
    d.name = spec;
    d.kind = DetectorKind::Custom;
    d.channels = table.columnNames;
    if (d.channels.empty())
        for (size_t c = 0; c < table.columns.size(); ++c) d.channels.push_back(fmt::format("ch{}", c + 1));
    for (size_t c = 0; c < d.channels.size(); ++c)
        if (d.channels[c].empty()) d.channels[c] = fmt::format("ch{}", c + 1);
    d.units = "the table's sensitivity unit × W·sr⁻¹·m⁻²·nm⁻¹ × nm";
    d.source = path.string();
    d.grid = grid;
    d.integration = integration;
    d.weights = weightsFromTable(table, path.string(), grid, quadratureWeights(grid, integration));
    return d;
}

[[noreturn]] void unknownDetector(const std::string& spec, const SpectrumLibrary& library, const Where& where) {
    std::vector<std::string> names = detectorNames(library);
    // Names are lower case; "CIE1931" is a capitalization slip, not a different detector.
    std::string lower = spec;
    for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    std::string suggestion = closestMatch(lower, names);
    if (suggestion.empty()) {
        // "camera:nikon" is a prefix of one name, not a typo of it: offer the name it starts.
        for (const auto& n : names)
            if (lower.size() >= 3 && startsWith(n, lower)) {
                suggestion = n;
                break;
            }
    }
    std::string known;
    for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
    known += ", csv:PATH";
    if (!suggestion.empty())
        failInput(where, "unknown detector '{}'; did you mean '{}'? (known: {})", spec, suggestion, known);
    failInput(where, "unknown detector '{}' (known: {})", spec, known);
}

}  // namespace

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

std::vector<std::string> detectorNames(const SpectrumLibrary& library) {
    std::vector<std::string> names = {"cie1931", "cie1964"};
    for (const auto& c : cameraNames(library)) names.push_back(kCameraPrefix + c);
    for (const auto& f : filmNames(library)) names.push_back(kFilmPrefix + f);
    return names;
}

Detector makeDetector(const std::string& spec, const SpectrumLibrary& library, const Grid& grid,
                      Integration integration, const Where& where) {
    if (spec == "cie1931") return observer(spec, kCie1931Observer, library, grid, integration);
    if (spec == "cie1964") return observer(spec, "observers/cie1964_10deg", library, grid, integration);
    if (startsWith(spec, kCsvPrefix)) return customCsv(spec, spec.substr(4), grid, integration, where);
    if (startsWith(spec, kCameraPrefix)) {
        std::string name = spec.substr(7);
        auto cams = cameraNames(library);
        if (std::find(cams.begin(), cams.end(), name) != cams.end())
            return camera(spec, name, library, grid, integration, where);
    }
    if (startsWith(spec, kFilmPrefix)) {
        std::string name = spec.substr(5);
        auto films = filmNames(library);
        if (std::find(films.begin(), films.end(), name) != films.end()) {
            Detector d = makeFilmLayers(name, library, grid, integration, where);
            d.name = spec;
            return d;
        }
    }
    unknownDetector(spec, library, where);
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
