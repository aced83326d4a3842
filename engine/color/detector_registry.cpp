#include "color/detector_registry.h"

#include "color/cie_xyz.h"
#include "color/film.h"
#include "core/file_reads.h"
#include "spectral/csv.h"
#include "spectral/resampling.h"
#include "spectral/spectrum.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <functional>

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

// One row per kind of detector spec: an exact name ("cie1931") or a prefix ("camera:"); for a
// prefix, the names it knows after it (for help, suggestions and the check that a name exists;
// none for csv:, whose names are paths), and its maker.
struct DetectorMaker {
    std::string spec;  // the exact spec, or a prefix ending in ':'
    std::function<std::vector<std::string>(const SpectrumLibrary&)> names;  // a prefix's names; null: any
    std::function<Detector(const std::string& spec, const std::string& name, const SpectrumLibrary&, const Grid&,
                           Integration, const Where&)>
        make;
    bool prefix() const { return !spec.empty() && spec.back() == ':'; }
};

const std::vector<DetectorMaker>& detectorMakers() {
    static const std::vector<DetectorMaker> makers = {
        {"cie1931", nullptr,
         [](const std::string& spec, const std::string&, const SpectrumLibrary& library, const Grid& grid,
            Integration integration, const Where&) {
             return observerDetector(spec, kCie1931Observer, library, grid, integration);
         }},
        {"cie1964", nullptr,
         [](const std::string& spec, const std::string&, const SpectrumLibrary& library, const Grid& grid,
            Integration integration, const Where&) {
             return observerDetector(spec, "observers/cie1964_10deg", library, grid, integration);
         }},
        {kCsvPrefix, nullptr,
         [](const std::string& spec, const std::string& path, const SpectrumLibrary&, const Grid& grid,
            Integration integration, const Where& where) { return customCsv(spec, path, grid, integration, where); }},
        {kCameraPrefix, cameraNames, camera},
        {kFilmPrefix, filmNames,
         [](const std::string& spec, const std::string& name, const SpectrumLibrary& library, const Grid& grid,
            Integration integration, const Where& where) {
             Detector d = makeFilmLayers(name, library, grid, integration, where);
             d.name = spec;
             return d;
         }},
    };
    return makers;
}

}  // namespace

std::vector<std::string> detectorNames(const SpectrumLibrary& library) {
    std::vector<std::string> names;
    for (const DetectorMaker& m : detectorMakers()) {
        if (!m.prefix()) names.push_back(m.spec);
        else if (m.names)
            for (const std::string& n : m.names(library)) names.push_back(m.spec + n);
    }
    return names;
}

Detector makeDetector(const std::string& spec, const SpectrumLibrary& library, const Grid& grid,
                      Integration integration, const Where& where) {
    for (const DetectorMaker& m : detectorMakers()) {
        if (m.prefix() ? !startsWith(spec, m.spec) : spec != m.spec) continue;
        const std::string name = m.prefix() ? spec.substr(m.spec.size()) : spec;
        if (m.names) {
            const std::vector<std::string> known = m.names(library);
            if (std::find(known.begin(), known.end(), name) == known.end()) continue;
        }
        return m.make(spec, name, library, grid, integration, where);
    }
    unknownDetector(spec, library, where);
}

}  // namespace metamer
