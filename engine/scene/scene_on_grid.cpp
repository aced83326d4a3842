#include "scene/scene_on_grid.h"

#include <algorithm>

namespace metamer {

namespace {

std::vector<double> onGrid(const SceneSpectrum& s, const Grid& grid, CoveragePolicy policy) {
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
        warn(s.where, what + "; bands outside the data are 0");
    }
    return resample(s.spectrum, grid);
}

}  // namespace

SceneOnGrid resampleScene(const Scene& scene, const Grid& grid, CoveragePolicy policy) {
    SceneOnGrid out;
    out.grid = grid;
    out.wavelengths_nm = grid.wavelengths();
    for (const auto& light : scene.lights) {
        auto e = onGrid(light.spectrum, grid, policy);
        for (double& v : e) v *= light.scale;
        out.lights.push_back(std::move(e));
    }
    for (const auto& m : scene.materials) {
        MaterialOnGrid g;
        g.diffuse = onGrid(m.diffuse, grid, policy);
        g.specular = onGrid(m.specular, grid, policy);
        g.gloss = m.gloss;
        if (m.fluorescence) {
            const Fluorescence& f = *m.fluorescence;
            g.fluorescent = true;
            g.quantum_yield = f.quantum_yield;
            g.excitation = onGrid(f.excitation, grid, policy);
            const Spectrum& em = f.emission.spectrum;
            if (em.isConstant())
                failInput(f.emission.where, "an emission spectrum must be sampled data, not a constant");
            double area = em.integral();
            if (!(area > 0.0))
                failInput(f.emission.where, "emission spectrum '{}' has no positive area", em.source);
            g.emission = onGrid(f.emission, grid, policy);
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
    return out;
}

}  // namespace metamer
