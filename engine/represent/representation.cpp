#include "represent/representation.h"

#include "spectral/csv.h"

#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>

namespace metamer {

namespace {

// 1 nm weights (wavelength_nm, 3 columns) summed into the grid's bands: a 1 nm sample at λ covers
// [λ − ½, λ + ½] and is shared between bands in proportion to the overlap.
std::vector<std::vector<double>> rebin(const SpectralTable& t, const Grid& grid) {
    std::vector<std::vector<double>> w(t.columns.size(), std::vector<double>(grid.bands(), 0.0));
    double h = 0.5 * grid.step_nm;
    for (size_t i = 0; i < t.wavelengths_nm.size(); ++i) {
        double lo = t.wavelengths_nm[i] - 0.5, hi = t.wavelengths_nm[i] + 0.5;
        int b0 = std::max(0, int(std::floor((lo - grid.start_nm + h) / grid.step_nm)));
        int b1 = std::min(grid.bands() - 1, int(std::floor((hi - grid.start_nm + h) / grid.step_nm)));
        for (int b = b0; b <= b1; ++b) {
            double c = grid.wavelength(b);
            double overlap = std::min(hi, c + h) - std::max(lo, c - h);
            if (overlap <= 0) continue;
            for (size_t k = 0; k < t.columns.size(); ++k) w[k][b] += t.columns[k][i] * overlap;
        }
    }
    return w;
}

std::vector<double> apply(const std::vector<std::vector<double>>& analysis, const std::vector<double>& v) {
    std::vector<double> out(analysis.size(), 0.0);
    for (size_t c = 0; c < analysis.size(); ++c)
        for (size_t b = 0; b < v.size(); ++b) out[c] += analysis[c][b] * v[b];
    return out;
}

}  // namespace

std::string Mode::name() const {
    switch (kind) {
        case ModeKind::Full: return "full";
        case ModeKind::Rgb: return "rgb";
        case ModeKind::Ac1c2: return fmt::format("ac1c2:{}", samples);
    }
    return "?";
}

Mode parseMode(const std::string& text, const Where& where) {
    Mode m;
    if (text == "full") return m;
    if (text == "rgb") {
        m.kind = ModeKind::Rgb;
        return m;
    }
    if (text == "ac1c2" || text.rfind("ac1c2:", 0) == 0) {
        m.kind = ModeKind::Ac1c2;
        m.samples = 4;
        if (text.size() > 5) {
            char* end = nullptr;
            long n = std::strtol(text.c_str() + 6, &end, 10);
            if (*end != '\0' || n < 3 || n > 8)
                failInput(where, "'{}': the AC1C2 quadrature has 3 to 8 samples, e.g. ac1c2:4", text);
            m.samples = int(n);
        }
        return m;
    }
    std::string near = closestMatch(text, {"full", "rgb", "ac1c2"});
    failInput(where, "'{}' is not a representation mode; expected full, rgb or ac1c2[:N]{}", text,
              near.empty() ? "" : fmt::format(" (did you mean '{}'?)", near));
}

Grid Representation::renderGrid() const {
    if (mode.spectral()) return grid;
    Grid g;
    g.start_nm = 0;
    g.end_nm = channels() - 1;
    g.step_nm = 1;
    return g;
}

Representation makeRepresentation(const Mode& mode, const Grid& grid, const SpectrumLibrary& library) {
    Representation r;
    r.mode = mode;
    r.grid = grid;
    const auto& root = library.root();
    if (mode.kind == ModeKind::Full) {
        for (double w : grid.wavelengths()) r.channelNames.push_back(fmt::format("{:g} nm", w));
        r.description = fmt::format("full spectral, {} bands {} nm", grid.bands(), grid.str());
        return r;
    }
    if (mode.kind == ModeKind::Rgb) {
        r.reflectanceAnalysis = rebin(readSpectralTable(root / "quadrature" / "rgb_weights.csv", 3), grid);
        r.lightAnalysis = rebin(readSpectralTable(root / "quadrature" / "rgb_light_weights.csv", 3), grid);
        std::ifstream in(root / "quadrature" / "rgb.json");
        if (!in) failInput(Where{(root / "quadrature" / "rgb.json").string()}, "cannot open the rgb mode's matrices");
        nlohmann::json j = nlohmann::json::parse(in);
        r.toXyz.assign(3, std::vector<double>(3));
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) r.toXyz[i][k] = j.at("linear_sRGB_to_XYZ").at(i).at(k).get<double>();
        r.channelNames = {"R", "G", "B"};
        r.description = "rgb: linear sRGB per light and per reflectance (D65 white = 1), multiplied per channel";
        return r;
    }
    // AC1C2: N samples; a band-valued spectrum is read at λ_k by linear interpolation between
    // band centres.
    auto path = root / "quadrature" / fmt::format("ac1c2_{}.csv", mode.samples);
    SpectralTable t = readSpectralTable(path, 3);
    size_t n = t.wavelengths_nm.size();
    r.toXyz.assign(3, std::vector<double>(n));
    r.lightAnalysis.assign(n, std::vector<double>(grid.bands(), 0.0));
    for (size_t k = 0; k < n; ++k) {
        double l = t.wavelengths_nm[k];
        double x = (l - grid.start_nm) / grid.step_nm;
        if (x < 0 || x > grid.bands() - 1)
            failInput(Where{path.string()}, "sample {:g} nm lies outside the grid {} nm", l, grid.str());
        int b = std::min(int(std::floor(x)), grid.bands() - 2);
        double f = x - b;
        if (grid.bands() == 1) {
            r.lightAnalysis[k][0] = 1.0;
        } else {
            r.lightAnalysis[k][b] = 1.0 - f;
            r.lightAnalysis[k][b + 1] = f;
        }
        for (int c = 0; c < 3; ++c) r.toXyz[c][k] = t.columns[c][k];
        r.channelNames.push_back(fmt::format("{:.1f} nm", l));
    }
    r.reflectanceAnalysis = r.lightAnalysis;
    r.description = fmt::format("ac1c2:{}: point samples at {} nm, Meyer's AC1C2 quadrature", n,
                                fmt::join(r.channelNames, ", "));
    return r;
}

std::vector<double> lightChannels(const Representation& r, const std::vector<double>& bands) {
    return r.mode.spectral() ? bands : apply(r.lightAnalysis, bands);
}

SceneOnGrid represent(const SceneOnGrid& spectra, const Representation& r, const Scene& scene) {
    if (r.mode.spectral()) return spectra;
    SceneOnGrid out;
    out.grid = r.renderGrid();
    out.wavelengths_nm = out.grid.wavelengths();
    for (const auto& e : spectra.lights) out.lights.push_back(apply(r.lightAnalysis, e));
    for (size_t m = 0; m < spectra.materials.size(); ++m) {
        const MaterialOnGrid& src = spectra.materials[m];
        MaterialOnGrid g;
        g.diffuse = apply(r.reflectanceAnalysis, src.diffuse);
        g.specular = apply(r.reflectanceAnalysis, src.specular);
        g.gloss = src.gloss;
        if (src.fluorescent)
            warn(Where{scene.file.string(), "materials." + scene.materials[m].name + ".fluorescence"},
                 fmt::format("the {} mode has no wavelengths: fluorescence is left out", r.mode.name()));
        out.materials.push_back(std::move(g));
    }
    return out;
}

}  // namespace metamer
