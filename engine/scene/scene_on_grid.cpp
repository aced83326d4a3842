#include "scene/scene_on_grid.h"

#include <algorithm>
#include <cmath>

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

}  // namespace

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
    for (const auto& m : scene.materials) {
        MaterialOnGrid g;
        g.diffuse = onGrid(m.diffuse, grid, policy, gaps);
        g.specular = onGrid(m.specular, grid, policy, gaps);
        g.gloss = m.gloss;
        if (m.fluorescence) {
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
                if (g.diffuse[i] + g.excitation[i] > worst) {
                    worst = g.diffuse[i] + g.excitation[i];
                    worstNm = out.wavelengths_nm[i];
                }
            if (worst > 1.0 + 1e-9)
                warn(f.excitation.where,
                     fmt::format("diffuse + excitation = {:.3f} > 1 at {:g} nm: the material reflects "
                                 "and absorbs more than the light it receives",
                                 worst, worstNm));
        }
        out.materials.push_back(std::move(g));
    }
    warnGaps(gaps, grid);
    return out;
}

}  // namespace metamer
