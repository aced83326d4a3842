#include "scene/scene_on_grid.h"

#include "core/cpu_count.h"
#include "spectral/resampling.h"

#include "spectral/library.h"
#include "color/rgb_upsampling.h"
#include "core/memory_limits.h"
#include "scene/texture.h"
#include "spectral/kubelka_munk.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <thread>
#include <unordered_map>

namespace metamer {

namespace {

// Spectra that miss part of the grid, grouped by kind and data range so that a chart of 24
// patches measured over the same range gives one warning, not 24.
struct Gap {
    SpectrumKind kind;
    double lo, hi;
    std::vector<const SceneSpectrum*> spectra;
};
std::vector<double> onGrid(const SceneSpectrum& s, const Grid& grid, CoveragePolicy policy, std::vector<Gap>& gaps) {
    CoverageGap gap = coverage(s.spectrum, grid);
    if (!gap.overlaps)
        failInput(s.where, "{} spectrum '{}' covers {:g}–{:g} nm, entirely outside the grid {:g}–{:g} nm",
                  kindName(s.kind), s.spectrum.source, gap.data_lo, gap.data_hi, grid.start_nm,
                  grid.end_nm);
    if (!gap.covered) {
        std::string what = fmt::format(
            "{} spectrum '{}' covers {:g}–{:g} nm but the grid is {:g}–{:g} nm", kindName(s.kind),
            s.spectrum.source, gap.data_lo, gap.data_hi, grid.start_nm, grid.end_nm);
        if (policy == CoveragePolicy::Error) failInput(s.where, "{} (--strict-coverage)", what);
        bool grouped = false;
        for (Gap& g : gaps)
            if (g.kind == s.kind && g.lo == gap.data_lo && g.hi == gap.data_hi) {
                g.spectra.push_back(&s);
                grouped = true;
            }
        if (!grouped) gaps.push_back(Gap{s.kind, gap.data_lo, gap.data_hi, {&s}});
    }
    return resample(s.spectrum, grid);
}

void warnGaps(const std::vector<Gap>& gaps, const Grid& grid) {
    for (const Gap& g : gaps) {
        const SceneSpectrum& first = *g.spectra.front();
        if (g.spectra.size() == 1) {
            warn(first.where, fmt::format("{} spectrum '{}' covers {:g}–{:g} nm but the grid is {:g}–{:g} nm; bands "
                                          "outside the data are 0",
                                          kindName(g.kind), first.spectrum.source, g.lo, g.hi, grid.start_nm, grid.end_nm));
            continue;
        }
        std::string names;
        for (size_t i = 0; i < g.spectra.size() && i < 3; ++i)
            names += (i ? ", '" : "'") + g.spectra[i]->spectrum.source + "'";
        if (g.spectra.size() > 3) names += fmt::format(" and {} more", g.spectra.size() - 3);
        warn(first.where, fmt::format("{} {} spectra ({}) cover {:g}–{:g} nm but the grid is {:g}–{:g} nm; bands "
                                      "outside the data are 0",
                                      g.spectra.size(), kindName(g.kind), names, g.lo, g.hi, grid.start_nm, grid.end_nm));
    }
}

// A spectral texture's texels onto the grid. resample() is linear in the data's values, so the
// band values of every texel are one matrix times its channels: column i is the resampled "hat"
// that is 1 at channel i's wavelength and 0 at the others.
TextureOnGrid spectralTextureOnGrid(const Texture& t, const Grid& grid, CoveragePolicy policy, std::vector<Gap>& gaps,
                                    std::vector<SceneSpectrum>& keepAlive) {
    const int bands = grid.bands(), n = t.channels;
    SceneSpectrum probe;
    probe.kind = SpectrumKind::Reflectance;
    probe.where = t.where;
    probe.spectrum.wavelengths_nm = t.wavelengths_nm;
    probe.spectrum.values.assign(n, 1.0);
    probe.spectrum.source = t.file.filename().string();
    keepAlive.push_back(probe);  // gaps point at it until warnGaps
    onGrid(keepAlive.back(), grid, policy, gaps);  // coverage: errors and grouped warnings
    std::vector<double> m(size_t(bands) * n, 0.0);  // [band][channel]
    for (int i = 0; i < n; ++i) {
        Spectrum hat;
        hat.wavelengths_nm = t.wavelengths_nm;
        hat.values.assign(n, 0.0);
        hat.values[i] = 1.0;
        std::vector<double> col = resample(hat, grid);
        for (int b = 0; b < bands; ++b) m[size_t(b) * n + i] = col[b];
    }
    TextureOnGrid out;
    out.width = t.width;
    out.height = t.height;
    out.channels = bands;
    out.data.resize(size_t(t.width) * t.height * bands);
    for (size_t p = 0; p < size_t(t.width) * t.height; ++p) {
        const float* in = &t.texels[p * n];
        float* o = &out.data[p * bands];
        for (int b = 0; b < bands; ++b) {
            double sum = 0.0;
            const double* row = &m[size_t(b) * n];
            for (int i = 0; i < n; ++i) sum += row[i] * in[i];
            o[b] = float(sum);
        }
    }
    return out;
}

// An RGB texture up-sampled texel by texel (color/rgb_upsampling.h); 8-bit images have few
// distinct colours, so each colour is up-sampled once.
TextureOnGrid rgbTextureOnGrid(const Texture& t, const Grid& grid, const RgbUpsampler& up) {
    const int bands = grid.bands();
    TextureOnGrid out;
    out.width = t.width;
    out.height = t.height;
    out.channels = bands;
    out.data.resize(size_t(t.width) * t.height * bands);
    std::unordered_map<uint64_t, size_t> seen;  // colour → texel that has its bands
    auto key = [](const float* c) {
        uint64_t h = 1469598103934665603ull;
        for (int k = 0; k < 3; ++k) {
            uint32_t bits;
            std::memcpy(&bits, &c[k], 4);
            h = (h ^ bits) * 1099511628211ull;
        }
        return h;
    };
    for (size_t p = 0; p < size_t(t.width) * t.height; ++p) {
        const float* c = &t.texels[p * 3];
        float* o = &out.data[p * bands];
        auto [it, fresh] = seen.try_emplace(key(c), p);
        const float* done = fresh ? nullptr : &t.texels[it->second * 3];
        if (done && done[0] == c[0] && done[1] == c[1] && done[2] == c[2]) {
            std::memcpy(o, &out.data[it->second * bands], sizeof(float) * bands);
            continue;
        }
        std::vector<double> v = up.bands(glm::dvec3(c[0], c[1], c[2]), grid);
        for (int b = 0; b < bands; ++b) o[b] = float(v[b]);
    }
    return out;
}

// The Donaldson matrix on the grid, with the coverage policy applied to each axis as to a
// spectrum: entirely outside is an error, partly outside a warning (or an error when strict).
std::vector<double> matrixOnGrid(const SceneMatrix& m, const Grid& grid, CoveragePolicy policy) {
    const BispectralMatrix& d = m.matrix;
    const CoverageGap in = coverageOf(d.in_nm, grid), out = coverageOf(d.out_nm, grid);
    for (const auto& [gap, axis] : {std::pair{in, "excitation (λin)"}, std::pair{out, "emission (λout)"}})
        if (!gap.overlaps)
            failInput(m.where, "Donaldson matrix '{}': its {} wavelengths cover {:g}–{:g} nm, entirely outside the grid "
                      "{:g}–{:g} nm",
                      d.source, axis, gap.data_lo, gap.data_hi, grid.start_nm, grid.end_nm);
    if (!in.covered || !out.covered) {
        std::string what = fmt::format(
            "Donaldson matrix '{}' covers λin {:g}–{:g} nm and λout {:g}–{:g} nm but the grid is {:g}–{:g} nm",
            d.source, in.data_lo, in.data_hi, out.data_lo, out.data_hi, grid.start_nm, grid.end_nm);
        if (policy == CoveragePolicy::Error) failInput(m.where, "{} (--strict-coverage)", what);
        warn(m.where, what + "; bands outside the data are 0");
    }
    std::vector<double> r = resampleMatrix(d, grid);
    for (double& v : r) {
        v *= m.scale;
        if (!std::isfinite(v))
            failInput(m.where, "Donaldson matrix '{}' × scale {:g} overflows a double", d.source, m.scale);
    }
    return r;
}

// Photons: what a matrix material re-emits per photon it receives at λi is
// Σ_o D̄(i, o)·(λo/λi)·Δλ (= Φ·a(λi) for the rank-one form), and with what it reflects that cannot
// exceed 1. Only the emission inside the grid is counted. A diffuse texture's reflectance is known
// only per texel, so with one only the re-emitted photons are checked.
void photonBalance(const MaterialOnGrid& g, const std::vector<double>& nm, double step, const Where& where) {
    const size_t n = nm.size();
    double worst = 0.0, worstNm = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double yield = 0.0;
        for (size_t o = 0; o < n; ++o) yield += g.donaldson[i * n + o] * nm[o] / nm[i] * step;
        const double reflected = g.diffuseTexture >= 0 ? 0.0 : g.diffuse[i];
        if (reflected + yield > worst) {
            worst = reflected + yield;
            worstNm = nm[i];
        }
    }
    if (worst > 1.0 + 1e-9)
        warn(where, fmt::format("diffuse + photons re-emitted per photon received = {:.3f} > 1 at {:g} nm: the "
                                "material reflects and re-emits more light than it receives (does the matrix carry "
                                "the reflectance on its diagonal?)",
                                worst, worstNm));
}

// n(λ) at each band centre `nm`, checked: a Sellmeier or Cauchy formula can pass through a pole
// (n² < 0, whose root is not a number) or below 1 on the grid. Errors name `where` and how the
// scene gave n (`source`).
std::vector<double> indexOnGrid(const RefractiveIndex& ior, const std::string& source, const Where& where,
                                const std::vector<double>& nm) {
    std::vector<double> out;
    for (double l : nm) {
        const double n = ior.at(l);
        if (!(n >= 1.0 && n <= 5.0))
            failInput(where, "the refractive index ({}) is {} at {:g} nm; expected 1 … 5 over the grid", source,
                      std::isnan(n) ? std::string("not a real number (n² < 0: the formula is past a pole)")
                                    : fmt::format("{:g}", n),
                      l);
        out.push_back(n);
    }
    return out;
}

// A paint's films on the grid (Material::Paint): K and S per band for each layer (the layer's own
// plus its pigments' cᵢkᵢ and cᵢsᵢ, m⁻¹), the substrate and Saunderson's k1 and k2 per band.
struct PaintOnGrid {
    std::vector<std::vector<KubelkaMunkConstants>> films;  // [layer][band]
    std::vector<double> thickness_m;        // per layer
    int mapped = -1;                        // the layer whose thickness the map scales
    std::vector<double> substrate, k1, k2;  // per band; k1, k2 empty without a surface
    bool surface = false;

    // The body reflectance in band b with the mapped layer's thickness × `factor`.
    double body(size_t b, double factor = 1.0) const {
        double r = substrate.empty() ? 0.0 : substrate[b];
        for (size_t l = 0; l < films.size(); ++l) {
            const double x = int(l) == mapped ? thickness_m[l] * factor : thickness_m[l];
            r = kubelkaMunkOverSubstrate(films[l][b], x, r);
        }
        return surface ? saundersonBody(r, k1[b], k2[b]) : r;
    }
};

PaintOnGrid paintOnGrid(const Material::Paint& paint, const std::vector<MaterialOnGrid>& earlier, const Grid& grid,
                        const std::vector<double>& nm, CoveragePolicy policy, std::vector<Gap>& gaps) {
    PaintOnGrid p;
    const size_t bands = size_t(grid.bands());
    for (size_t l = 0; l < paint.layers.size(); ++l) {
        const Material::Paint::Layer& layer = paint.layers[l];
        std::vector<double> K(bands, 0.0), S(bands, 0.0);
        if (layer.K) K = onGrid(*layer.K, grid, policy, gaps);
        if (layer.S) S = onGrid(*layer.S, grid, policy, gaps);
        std::vector<std::vector<double>> k, s;  // [pigment][band]
        for (const Material::Paint::Pigment& pigment : layer.pigments) {
            k.push_back(onGrid(pigment.k, grid, policy, gaps));
            s.push_back(onGrid(pigment.s, grid, policy, gaps));
        }
        std::vector<KubelkaMunkPigment> inBand(layer.pigments.size());
        for (size_t b = 0; b < bands && !inBand.empty(); ++b) {
            for (size_t i = 0; i < inBand.size(); ++i) inBand[i] = {layer.pigments[i].concentration, k[i][b], s[i][b]};
            const KubelkaMunkCoefficients mixed = kubelkaMunkMix(inBand, {K[b], S[b]});
            K[b] = mixed.K;
            S[b] = mixed.S;
        }
        for (size_t b = 0; b < bands; ++b)
            if (!(K[b] >= 0.0 && S[b] >= 0.0 && std::isfinite(K[b] + S[b])))
                failInput(layer.where, "the layer's K = {:g} and S = {:g} m⁻¹ at {:g} nm; expected finite values ≥ 0",
                          K[b], S[b], nm[b]);
        std::vector<KubelkaMunkConstants> film(bands);
        for (size_t b = 0; b < bands; ++b) film[b] = kubelkaMunkConstants(K[b], S[b]);
        p.films.push_back(std::move(film));
        p.thickness_m.push_back(layer.thickness_m);
        if (layer.thicknessMap >= 0) p.mapped = int(l);
    }
    if (paint.substrate) p.substrate = onGrid(*paint.substrate, grid, policy, gaps);
    if (paint.substrateMaterial >= 0) p.substrate = earlier[size_t(paint.substrateMaterial)].diffuse;
    if (paint.surface) {
        p.surface = true;
        const Material::Paint::Surface& s = *paint.surface;
        if (s.ior) {
            std::unordered_map<double, std::pair<double, double>> byIndex;  // k2 is an integral: once per n
            for (double n : indexOnGrid(*s.ior, s.iorSource, s.where.child("ior"), nm)) {
                auto it = byIndex.find(n);
                if (it == byIndex.end())
                    it = byIndex.emplace(n, std::pair{saundersonK1(n), internalDiffuseReflectance(n)}).first;
                p.k1.push_back(it->second.first);
                p.k2.push_back(it->second.second);
            }
        } else {
            p.k1.assign(bands, s.k1);
            p.k2.assign(bands, s.k2);
        }
    }
    return p;
}

// The paint's reflectance per texel of its thickness map: a spectral texture. Computed once per
// distinct texel value (an 8-bit map has at most 256, a 16-bit one 65 536), the values split
// between threads.
TextureOnGrid paintTexture(const PaintOnGrid& p, const Texture& map, size_t bands) {
    std::unordered_map<float, uint32_t> index;  // texel value → its row in `spectra`
    std::vector<float> values;
    std::vector<uint32_t> row(map.texels.size());
    for (size_t i = 0; i < map.texels.size(); ++i) {
        auto [it, fresh] = index.emplace(map.texels[i], uint32_t(values.size()));
        if (fresh) values.push_back(map.texels[i]);
        row[i] = it->second;
    }
    std::vector<float> spectra(values.size() * bands);
    auto compute = [&](size_t begin, size_t end) {
        for (size_t v = begin; v < end; ++v)
            for (size_t b = 0; b < bands; ++b) spectra[v * bands + b] = float(p.body(b, double(values[v])));
    };
    const size_t threads = std::clamp<size_t>(values.size() / 1024, 1, size_t(usableCpuCount()));
    std::vector<std::thread> pool;
    for (size_t t = 1; t < threads; ++t)
        pool.emplace_back(compute, values.size() * t / threads, values.size() * (t + 1) / threads);
    compute(0, values.size() / threads);
    for (std::thread& t : pool) t.join();
    TextureOnGrid t;
    t.width = map.width;
    t.height = map.height;
    t.channels = int(bands);
    t.data.resize(map.texels.size() * bands);
    for (size_t i = 0; i < row.size(); ++i)
        std::memcpy(&t.data[i * bands], &spectra[size_t(row[i]) * bands], bands * sizeof(float));
    return t;
}

}  // namespace

uint64_t textureMemory(const Scene& scene, const Grid& grid) {
    uint64_t bytes = 0;
    for (const Texture& t : scene.textures)
        if (t.kind != Texture::Kind::Scalar)
            bytes += uint64_t(t.width) * t.height * (t.kind == Texture::Kind::Normal ? 3 : grid.bands()) * 4;
    // A thickness map becomes a spectral texture for each paint that uses it.
    for (const Material& m : scene.materials)
        if (m.paint && m.paint->thicknessMap() >= 0) {
            const Texture& t = scene.textures[size_t(m.paint->thicknessMap())];
            bytes += uint64_t(t.width) * t.height * grid.bands() * 4;
        }
    return bytes;
}

SceneOnGrid resampleScene(const Scene& scene, const Grid& grid, CoveragePolicy policy) {
    std::vector<Gap> gaps;
    SceneOnGrid out;
    out.grid = grid;
    out.wavelengths_nm = grid.wavelengths();
    for (const auto& light : scene.lights) {
        auto e = onGrid(light.spectrum, grid, policy, gaps);
        for (double& v : e) {
            v *= light.scale;
            if (!std::isfinite(v))
                failInput(light.spectrum.where, "light spectrum '{}' × scale {:g} overflows a double",
                          light.spectrum.spectrum.source, light.scale);
        }
        out.lights.push_back(std::move(e));
    }
    if (uint64_t bytes = textureMemory(scene, grid); bytes > textureMemoryLimit())
        failInput(Where{scene.file.string(), "materials"},
                  "the scene's textures would take {:.1f} GiB on the grid {} nm ({} bands × 4 bytes per texel); the "
                  "limit is {} (8 GiB, or a quarter of this machine's memory when less): use smaller textures or a "
                  "coarser grid",
                  double(bytes) / double(1 << 30), grid.str(), grid.bands(), memorySize(textureMemoryLimit()));
    std::vector<SceneSpectrum> textureProbes;
    textureProbes.reserve(scene.textures.size());
    for (const Texture& t : scene.textures) {
        if (t.kind == Texture::Kind::Spectral) {
            out.textures.push_back(spectralTextureOnGrid(t, grid, policy, gaps, textureProbes));
        } else if (t.kind == Texture::Kind::Rgb) {
            out.textures.push_back(rgbTextureOnGrid(t, grid, RgbUpsampler::srgb(SpectrumLibrary())));
        } else if (t.kind == Texture::Kind::Scalar) {
            // Read by no shader: each paint that uses it gets its own spectral texture, below. A
            // 1×1 stand-in keeps the indices of Scene::textures.
            TextureOnGrid placeholder;
            placeholder.width = placeholder.height = placeholder.channels = 1;
            placeholder.data = {0.0f};
            out.textures.push_back(std::move(placeholder));
        } else {
            TextureOnGrid n;
            n.width = t.width;
            n.height = t.height;
            n.channels = 3;
            n.normals = true;
            n.data = t.texels;
            out.textures.push_back(std::move(n));
        }
    }
    for (const auto& m : scene.materials) {
        MaterialOnGrid g;
        g.diffuseTexture = m.textures.diffuse;
        g.specularTexture = m.textures.specular;
        g.normalTexture = m.textures.normal;
        g.diffuse = onGrid(m.diffuse, grid, policy, gaps);
        // What the energy check below compares with the excitation: the largest body reflectance.
        std::vector<double> brightest = g.diffuse;
        if (m.paint) {
            // Kubelka–Munk, once per scene: the body reflectance per band, or per texel of a
            // thickness map (a spectral texture that the diffuse slot reads, ρd = 1).
            const PaintOnGrid paint = paintOnGrid(*m.paint, out.materials, grid, out.wavelengths_nm, policy, gaps);
            const int map = m.paint->thicknessMap();
            for (size_t b = 0; b < g.diffuse.size(); ++b) g.diffuse[b] = map >= 0 ? 1.0 : paint.body(b);
            brightest = g.diffuse;
            if (map >= 0) {
                out.textures.push_back(paintTexture(paint, scene.textures[size_t(map)], g.diffuse.size()));
                g.diffuseTexture = int(out.textures.size() - 1);
                const TextureOnGrid& t = out.textures.back();
                brightest.assign(g.diffuse.size(), 0.0);
                for (size_t i = 0; i < t.data.size(); ++i)
                    brightest[i % brightest.size()] = std::max(brightest[i % brightest.size()], double(t.data[i]));
            }
        }
        g.specular = onGrid(m.specular, grid, policy, gaps);
        g.gloss = m.gloss;
        if (m.fluorescence && m.fluorescence->matrix) {
            g.fluorescent = true;
            g.donaldson = matrixOnGrid(*m.fluorescence->matrix, grid, policy);
            photonBalance(g, out.wavelengths_nm, grid.step_nm, m.fluorescence->matrix->where);
        } else if (m.fluorescence) {
            const Fluorescence& f = *m.fluorescence;
            g.fluorescent = true;
            g.quantum_yield = f.quantum_yield;
            g.excitation = onGrid(f.excitation, grid, policy, gaps);
            const Spectrum& em = f.emission.spectrum;
            if (em.isConstant())
                failInput(f.emission.where, "an emission spectrum must be sampled data, not a constant");
            double area = em.integral();
            if (!(area > 0.0) || !std::isfinite(area))
                failInput(f.emission.where, "emission spectrum '{}' has no positive, finite area", em.source);
            g.emission = onGrid(f.emission, grid, policy, gaps);
            for (double& v : g.emission) v /= area;
            // Energy: what is absorbed for fluorescence cannot also be reflected.
            double worst = 0.0, worstNm = 0.0;
            for (size_t i = 0; i < g.diffuse.size(); ++i)
                if (brightest[i] + g.excitation[i] > worst) {
                    worst = brightest[i] + g.excitation[i];
                    worstNm = out.wavelengths_nm[i];
                }
            if (worst > 1.0 + 1e-9)
                warn(f.excitation.where,
                     fmt::format("diffuse + excitation = {:.3f} > 1 at {:g} nm: the material reflects "
                                 "and absorbs more than the light it receives",
                                 worst, worstNm));
        }
        if (m.emitter) {
            g.emitted = onGrid(m.emitter->spectrum, grid, policy, gaps);
            for (double& v : g.emitted) {
                v *= m.emitter->scale;
                if (!std::isfinite(v))
                    failInput(m.emitter->spectrum.where, "spectrum '{}' × scale {:g} overflows a double",
                              m.emitter->spectrum.spectrum.source, m.emitter->scale);
            }
        }
        if (m.transmittance) g.transmittance = onGrid(*m.transmittance, grid, policy, gaps);
        if (m.slab) {
            g.slabThickness = m.slab->thickness_m;
            g.slabAbsorbance.assign(size_t(grid.bands()), 0.0);
            if (m.slab->absorbance) g.slabAbsorbance = onGrid(*m.slab->absorbance, grid, policy, gaps);
            g.ior = indexOnGrid(m.slab->ior, m.slab->iorSource, m.slab->iorWhere, out.wavelengths_nm);
        }
        if (m.isMedium()) {
            g.absorbance.assign(size_t(grid.bands()), 0.0);
            if (m.absorbance) g.absorbance = onGrid(*m.absorbance, grid, policy, gaps);
            for (const Material::Dye& dye : m.dyes) {
                // ε in L·mol⁻¹·cm⁻¹ × c in mol·L⁻¹ is an absorbance per cm: × 100 per metre.
                const std::vector<double> eps = onGrid(dye.absorptivity, grid, policy, gaps);
                for (size_t b = 0; b < eps.size(); ++b) {
                    g.absorbance[b] += 100.0 * eps[b] * dye.concentration;
                    // Each spectrum is bounded when read; their sum with the concentrations is not.
                    if (!(g.absorbance[b] <= kMaxAbsorbance))
                        failInput(dye.absorptivity.where,
                                  "material '{}' absorbs {:g} per metre at {:g} nm with this dye (its absorbance plus "
                                  "each dye's 100·ε·c); at most {:g}",
                                  m.name, g.absorbance[b], out.wavelengths_nm[b], kMaxAbsorbance);
                }
            }
        }
        out.materials.push_back(std::move(g));
    }
    warnGaps(gaps, grid);
    return out;
}

void TextureOnGrid::bilinear(const glm::dvec2& uv, double* out) const {
    const double px = (uv.x - std::floor(uv.x)) * width - 0.5, py = (uv.y - std::floor(uv.y)) * height - 0.5;
    const double x0 = std::floor(px), y0 = std::floor(py), fx = px - x0, fy = py - y0;
    auto wrap = [](long i, int n) { return int(((i % n) + n) % n); };
    const int xa = wrap(long(x0), width), xb = wrap(long(x0) + 1, width);
    const int ya = wrap(long(y0), height), yb = wrap(long(y0) + 1, height);
    const float *t00 = texel(xa, ya), *t10 = texel(xb, ya), *t01 = texel(xa, yb), *t11 = texel(xb, yb);
    for (int c = 0; c < channels; ++c)
        out[c] = (1 - fy) * ((1 - fx) * t00[c] + fx * t10[c]) + fy * ((1 - fx) * t01[c] + fx * t11[c]);
}

}  // namespace metamer
