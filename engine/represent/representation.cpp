#include "represent/representation.h"
#include "core/file_reads.h"
#include "core/json.h"

#include "spectral/csv.h"
#include "spectral/resampling.h"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>

namespace metamer {

namespace {

// A table of weights per nm (wavelength_nm, 3 columns) on the grid: each column is a function of λ,
// resampled by the grid's rule like every spectrum (spectral/resampling.h) and times Δλ, so that
// Σ_b weight_b·v_b is the Riemann sum of the display path. With `unitSum`, each column is scaled to
// sum to 1 on this grid (the rgb mode's white diffuser is exactly (1, 1, 1) whatever the grid).
std::vector<std::vector<double>> weightsOnGrid(const SpectralTable& t, const Grid& grid, bool unitSum) {
    const BandWeights bw = bandWeights(t.wavelengths_nm, grid);
    std::vector<std::vector<double>> w;
    for (const auto& column : t.columns) {
        std::vector<double> c = bw.apply(column);
        double sum = 0;
        for (double& x : c) sum += x *= grid.step_nm;
        if (unitSum && sum != 0)
            for (double& x : c) x /= sum;
        w.push_back(std::move(c));
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
        case ModeKind::Linear: return fmt::format("linear:{}", samples);
    }
    return "?";
}

void requireSpectralModeForSensor(const std::string& mode, const Where& where) {
    if (!parseMode(mode, where).spectral())
        failInput(where, "'{}' renders channels, not spectra; a sensor captures a spectral cube (mode full or linear:K)",
                  mode);
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
    if (text.rfind("linear:", 0) == 0) {
        char* end = nullptr;
        long k = std::strtol(text.c_str() + 7, &end, 10);
        if (*end != '\0' || end == text.c_str() + 7 || k < 1 || k > 12)
            failInput(where, "'{}': the linear model takes 1 to 12 basis functions, e.g. linear:6", text);
        m.kind = ModeKind::Linear;
        m.samples = int(k);
        return m;
    }
    std::string near = closestMatch(text, {"full", "rgb", "ac1c2", "linear:6"});
    failInput(where, "'{}' is not a representation mode; expected full, rgb, ac1c2[:N] or linear:K{}", text,
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

namespace {

// The distinct texels of a reflectance texture, read on a regular lattice of at most
// kBasisTexels texels (every texel of a smaller texture): a texture is analysed as that many
// materials would be, and exact duplicates (a chart's patches, a constant texture) count once.
constexpr int kBasisTexels = 1024;

std::vector<std::vector<double>> distinctTexels(const TextureOnGrid& t) {
    const int side = int(std::sqrt(double(kBasisTexels)));
    const int nx = std::min(t.width, side), ny = std::min(t.height, side);
    std::set<std::vector<float>> seen;
    std::vector<std::vector<double>> out;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            // Lattice points at texel centres spread over the whole texture.
            const int x = int((int64_t(2 * i + 1) * t.width) / (2 * nx)), y = int((int64_t(2 * j + 1) * t.height) / (2 * ny));
            const float* p = t.texel(x, y);
            std::vector<float> v(p, p + t.channels);
            if (seen.insert(v).second) out.emplace_back(v.begin(), v.end());
        }
    return out;
}

// Characteristic vectors of the spectra a pixel can hold — each light, and the light each
// material reflects (diffuse and specular, texel by texel where the reflectance is textured) and
// emits — normalized so no one spectrum dominates by its brightness; uncentred, as Peercy's
// characteristic-vector analysis.
void linearBasis(Representation& r, const SceneOnGrid& spectra) {
    const double dl = r.grid.step_nm;
    const auto bands = Eigen::Index(r.grid.bands());
    // The samples are the columns of S (bands × n), each scaled to Σ s²·Δλ = 1 and by √Δλ, so
    // that S·Sᵀ is the analysis's second-moment operator; its leading eigenvectors are the basis.
    // While n < bands they come from the Gram matrix Sᵀ·S (the same non-zero eigenvalues;
    // e = S·v/√λ); from n = bands on, S·Sᵀ is accumulated a block of `bands` columns at a time, so
    // memory stays at two bands × bands matrices however many texels and lights there are.
    Eigen::MatrixXd block(bands, bands), moment;
    Eigen::Index inBlock = 0;
    auto flush = [&] {
        if (moment.size() == 0) moment = Eigen::MatrixXd::Zero(bands, bands);
        moment.selfadjointView<Eigen::Lower>().rankUpdate(block.leftCols(inBlock));
        inBlock = 0;
    };
    auto add = [&](const std::vector<double>& s) {
        double n2 = 0;
        for (double x : s) n2 += x * x * dl;
        if (!(n2 > 0)) return;
        const double f = std::sqrt(dl / n2);
        for (Eigen::Index b = 0; b < bands; ++b) block(b, inBlock) = s[size_t(b)] * f;
        if (++inBlock == bands) flush();
    };
    std::vector<std::vector<std::vector<double>>> texels(spectra.textures.size());
    for (size_t t = 0; t < spectra.textures.size(); ++t)
        if (!spectra.textures[t].normals) texels[t] = distinctTexels(spectra.textures[t]);
    // ρ·E, or ρ·T·E for every distinct texel T of ρ's texture.
    auto addReflected = [&](const std::vector<double>& rho, int texture, const std::vector<double>& e) {
        std::vector<double> s(e.size());
        if (texture < 0) {
            for (size_t b = 0; b < s.size(); ++b) s[b] = rho[b] * e[b];
            add(s);
            return;
        }
        for (const auto& tex : texels[size_t(texture)]) {
            for (size_t b = 0; b < s.size(); ++b) s[b] = rho[b] * tex[b] * e[b];
            add(s);
        }
    };
    for (const auto& e : spectra.lights) {
        add(e);
        for (const auto& m : spectra.materials) {
            addReflected(m.diffuse, m.diffuseTexture, e);
            addReflected(m.specular, m.specularTexture, e);
        }
    }
    for (const auto& m : spectra.materials) {
        if (!m.fluorescent) continue;
        if (!m.isMatrix()) {
            add(m.emission);
            continue;
        }
        // A Donaldson matrix's emission shape depends on the light: add what each light makes it emit.
        const size_t nb = size_t(bands);
        for (const auto& e : spectra.lights) {
            std::vector<double> f(nb, 0.0);
            for (size_t i = 0; i < nb; ++i)
                for (size_t o = 0; o < nb; ++o) f[o] += m.donaldson[i * nb + o] * e[i];
            add(f);
        }
    }
    const bool gram = moment.size() == 0;  // fewer samples than bands: all still in the block
    if (gram && inBlock == 0) failInput(Where{"", "--mode"}, "linear: the scene has no light to analyse");
    if (!gram && inBlock > 0) flush();
    const auto samples = block.leftCols(inBlock);  // the Gram path's samples (none after a flush)
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(gram ? Eigen::MatrixXd(samples.transpose() * samples)
                                                               : moment);
    if (solver.info() != Eigen::Success) failRuntime("linear:{}: the eigen-decomposition did not converge", r.mode.samples);
    const Eigen::VectorXd& values = solver.eigenvalues();  // ascending
    const Eigen::Index last = values.size() - 1;
    double total = 0, kept = 0;
    for (Eigen::Index c = 0; c <= last; ++c) total += std::max(values(c), 0.0);
    const Eigen::Index k = std::min<Eigen::Index>(r.mode.samples, values.size());
    for (Eigen::Index c = 0; c < k && values(last - c) > 1e-12 * values(last); ++c) {
        const double lambda = values(last - c);
        Eigen::VectorXd x = gram ? Eigen::VectorXd(samples * solver.eigenvectors().col(last - c) / std::sqrt(lambda))
                                 : Eigen::VectorXd(solver.eigenvectors().col(last - c));
        std::vector<double> e(static_cast<size_t>(bands));
        for (Eigen::Index b = 0; b < bands; ++b) e[size_t(b)] = x(b) / std::sqrt(dl);  // Σ e²·Δλ = 1
        r.basis.push_back(std::move(e));
        kept += lambda;
    }
    r.energyKept = total > 0 ? kept / total : 1.0;
    if (r.basis.size() < size_t(r.mode.samples))
        warn(Where{"", "--mode"}, fmt::format("linear:{}: the scene's spectra span only {} dimensions; using {}",
                                              r.mode.samples, r.basis.size(), r.basis.size()));
}

}  // namespace

std::vector<double> project(const Representation& r, const std::vector<double>& v) {
    if (r.mode.kind != ModeKind::Linear) return v;
    std::vector<double> out(v.size(), 0.0);
    for (const auto& e : r.basis) {
        double c = 0;
        for (size_t b = 0; b < v.size(); ++b) c += e[b] * v[b] * r.grid.step_nm;
        for (size_t b = 0; b < v.size(); ++b) out[b] += c * e[b];
    }
    return out;
}

void projectCube(const Representation& r, std::vector<float>& data, int bands) {
    if (r.mode.kind != ModeKind::Linear) return;
    std::vector<double> v(bands);
    for (size_t p = 0; p + bands <= data.size(); p += bands) {
        for (int b = 0; b < bands; ++b) v[b] = data[p + b];
        v = project(r, v);
        for (int b = 0; b < bands; ++b) data[p + b] = float(v[b]);
    }
}

Representation makeRepresentation(const Mode& mode, const Grid& grid, const SpectrumLibrary& library,
                                  const SceneOnGrid* spectra) {
    Representation r;
    r.mode = mode;
    r.grid = grid;
    const auto& root = library.root();
    if (mode.kind == ModeKind::Linear) {
        if (!spectra) failRuntime("linear:K needs the scene's spectra to build its basis");
        for (double w : grid.wavelengths()) r.channelNames.push_back(fmt::format("{:g} nm", w));
        linearBasis(r, *spectra);
        r.description = fmt::format("linear:{}: Peercy 1993, {} basis functions from the scene's spectra keeping "
                                    "{:.6f} of their energy, products by projection",
                                    mode.samples, r.basis.size(), r.energyKept);
        return r;
    }
    if (mode.kind == ModeKind::Full) {
        for (double w : grid.wavelengths()) r.channelNames.push_back(fmt::format("{:g} nm", w));
        r.description = fmt::format("full spectral, {} bands {} nm", grid.bands(), grid.str());
        return r;
    }
    if (mode.kind == ModeKind::Rgb) {
        r.reflectanceAnalysis = weightsOnGrid(readSpectralTable(root / "quadrature" / "rgb_weights.csv", 3), grid, true);
        r.lightAnalysis = weightsOnGrid(readSpectralTable(root / "quadrature" / "rgb_light_weights.csv", 3), grid, false);
        const std::filesystem::path file = root / "quadrature" / "rgb.json";
        noteFileRead(file);
        const nlohmann::ordered_json j = parseJson(readWholeFile(file, Where{file.string()}, "rgb mode's matrices"), file.string());
        r.toXyz.assign(3, std::vector<double>(3));
        const auto* m = j.is_object() && j.contains("linear_sRGB_to_XYZ") ? &j["linear_sRGB_to_XYZ"] : nullptr;
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) {
                if (!m || !m->is_array() || m->size() != 3 || !(*m)[i].is_array() || (*m)[i].size() != 3 ||
                    !(*m)[i][k].is_number())
                    failInput(Where{file.string(), "linear_sRGB_to_XYZ"}, "expected a 3×3 array of numbers");
                r.toXyz[i][k] = (*m)[i][k].get<double>();
            }
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

DisplayChannels displayChannels(const Representation& r) {
    DisplayChannels c;
    c.mode = r.mode.name();
    c.description = r.description;
    if (r.mode.kind == ModeKind::Linear) {
        c.kind = DisplayChannels::Kind::Projected;
        c.basis = r.basis;
    } else if (!r.mode.spectral()) {
        c.kind = DisplayChannels::Kind::Reduced;
        c.lightAnalysis = r.lightAnalysis;
        c.toXyz = r.toXyz;
    }
    return c;
}

std::vector<double> lightChannels(const Representation& r, const std::vector<double>& bands) {
    if (r.mode.kind == ModeKind::Linear) return project(r, bands);
    return r.mode.spectral() ? bands : apply(r.lightAnalysis, bands);
}

SceneOnGrid represent(const SceneOnGrid& spectra, const Representation& r, const Scene& scene) {
    if (r.mode.kind == ModeKind::Linear) {
        // Peercy: lights are vectors in the basis; a material is the matrix ∫ e_i·ρ·e_j, which is
        // what multiplying the full reflectance by the projected light and projecting the result
        // computes. So: project the lights here, the rendered pixels after (projectCube).
        SceneOnGrid out = spectra;
        for (auto& e : out.lights) e = project(r, e);
        for (auto& m : out.materials)  // an emitted radiance is a light
            if (m.isEmitter()) m.emitted = project(r, m.emitted);
        return out;
    }
    if (r.mode.spectral()) return spectra;
    SceneOnGrid out;
    out.grid = r.renderGrid();
    out.wavelengths_nm = out.grid.wavelengths();
    for (const auto& e : spectra.lights) out.lights.push_back(apply(r.lightAnalysis, e));
    for (size_t m = 0; m < spectra.materials.size(); ++m) {
        // A copy, every spectrum transformed through the one seam (forEachSpectrum): reflectances
        // analysed into the mode's channels; fluorescence, which needs wavelengths, left out.
        MaterialOnGrid g = spectra.materials[m];
        if (g.fluorescent)
            warn(Where{scene.file.string(), "materials." + scene.materials[m].name + ".fluorescence"},
                 fmt::format("the {} mode has no wavelengths: fluorescence is left out", r.mode.name()));
        forEachSpectrum(g, [&](std::vector<double>& values, MaterialSpectrum kind, const char*) {
            switch (kind) {
                // A transmittance multiplies like a reflectance; an absorbance is analysed the same
                // way, as an RGB renderer carries an absorption coefficient per channel (the
                // exponential is taken of the reduced channels, not reduced after: the mode's error).
                // A slab's n(λ) likewise: the analysis of a constant is the constant, so clear glass of
                // one index stays itself, and a dispersive one gets a weighted n per channel.
                case MaterialSpectrum::Reflectance:
                case MaterialSpectrum::Transmittance:
                case MaterialSpectrum::Absorbance:
                case MaterialSpectrum::Index:
                    if (!values.empty()) values = metamer::apply(r.reflectanceAnalysis, values);
                    return;
                // An emitted radiance is a light in the mode's light channels.
                case MaterialSpectrum::Radiance:
                    if (!values.empty()) values = metamer::apply(r.lightAnalysis, values);
                    return;
                case MaterialSpectrum::Absorptance:
                case MaterialSpectrum::Emission:
                case MaterialSpectrum::Matrix: values.clear(); return;
            }
        });
        g.fluorescent = false;
        g.quantum_yield = 0.0;
        out.materials.push_back(std::move(g));
    }
    // Reflectance textures are analysed texel by texel, as the materials' spectra are; normal maps
    // are geometry and stay as they are.
    for (const TextureOnGrid& t : spectra.textures) {
        if (t.normals) {
            out.textures.push_back(t);
            continue;
        }
        TextureOnGrid c;
        c.width = t.width;
        c.height = t.height;
        c.channels = int(r.reflectanceAnalysis.size());
        c.data.resize(size_t(t.width) * t.height * c.channels);
        std::vector<double> v(t.channels);
        for (size_t p = 0; p < size_t(t.width) * t.height; ++p) {
            for (int b = 0; b < t.channels; ++b) v[b] = t.data[p * t.channels + b];
            std::vector<double> a = metamer::apply(r.reflectanceAnalysis, v);  // not std::apply (ADL)
            for (int k = 0; k < c.channels; ++k) c.data[p * c.channels + k] = float(a[k]);
        }
        out.textures.push_back(std::move(c));
    }
    return out;
}

}  // namespace metamer
