// Transparent materials (docs/scene-format.md, "Transparent materials"): a thin sheet's
// "transmittance", an absorbing medium's "absorbance" and "dyes", and a glass "slab" with its
// refractive index (read by scene/scene_reader.cpp, which paints' surfaces share) and thickness.
// Tests: engine/scene/material_reader_transparent_test.cpp, tests/transparency_test.cpp.
#include "scene/material_readers.h"

#include <cmath>
#include <tuple>

namespace metamer {

using namespace json_read;

namespace {

// "slab": {"ior": n, "thickness": d, "absorbance": a}: n a number, "N-BK7", {"sellmeier": {"B":
// [...], "C": [...]}}, {"cauchy": {"A": a, "B": b, "C": c}} or a table {"wavelengths_nm": [...],
// "values": [...]} (λ in µm for the formulas' coefficients, as glass catalogues give them).
Material::Slab readSlab(SceneReader& r, const Json& v, const Where& w) {
    asObject(v, w);
    checkKeys(v, w, {"ior", "thickness", "absorbance"}, "a slab");
    Material::Slab slab;
    slab.thickness_m = numberIn(require(v, w, "thickness", "the slab's thickness in metres"), w.child("thickness"), 0,
                                INFINITY, true, true, " m");
    if (const Json* a = find(v, "absorbance")) slab.absorbance = r.spectrum(*a, w.child("absorbance"), SpectrumKind::Absorbance);
    slab.iorWhere = w.child("ior");
    const Json& n = require(v, w, "ior", "a refractive index: a number, \"N-BK7\", {\"sellmeier\": ...}, "
                                            "{\"cauchy\": ...} or a table");
    std::tie(slab.ior, slab.iorSource) = r.refractiveIndex(n, slab.iorWhere);
    return slab;
}

}  // namespace

// A transparent material (docs/scene-format.md, "Transparent materials"): a thin sheet
// {"transmittance": T} or an absorbing medium {"absorbance": a, "dyes": [{"absorptivity": ε,
// "concentration": c}, …]} (either or both of a and dyes). It reflects nothing: the opaque
// material's keys are refused by name, so that a user does not believe a glass reflects.
Material readTransparentMaterial(SceneReader& r, Material m, const Json& v, const Where& w) {
    const bool sheet = find(v, "transmittance") != nullptr, glass = find(v, "slab") != nullptr;
    for (const char* k : {"diffuse", "specular", "gloss", "fluorescence", "textures"})
        if (find(v, k))
            failInput(w.child(k),
                      "not allowed in a transparent material ({}): a transparent material's reflection is its "
                      "own (a slab's Fresnel reflection) or none, and it does not fluoresce in this renderer "
                      "(docs/physics.md, \"Transparent objects\")",
                      glass   ? "it has a 'slab'"
                      : sheet ? "it has a 'transmittance'"
                              : "it has an 'absorbance' or 'dyes'");
    if (glass) {
        for (const char* k : {"transmittance", "absorbance", "dyes"})
            if (find(v, k))
                failInput(w.child(k),
                          "not allowed beside 'slab': a slab's own absorbance goes inside it "
                          "(\"slab\": {{\"absorbance\": ...}})");
        checkKeys(v, w, {"slab"}, "a slab material");
        m.slab = readSlab(r, *find(v, "slab"), w.child("slab"));
    } else if (sheet) {
        for (const char* k : {"absorbance", "dyes"})
            if (find(v, k))
                failInput(w.child(k),
                          "not allowed with 'transmittance': a material is either a thin sheet (a transmittance "
                          "per crossing) or an absorbing medium (an absorbance per metre inside a closed mesh)");
        checkKeys(v, w, {"transmittance"}, "a filter (a thin sheet)");
        m.transmittance = r.spectrum(*find(v, "transmittance"), w.child("transmittance"), SpectrumKind::Transmittance);
    } else {
        checkKeys(v, w, {"absorbance", "dyes"}, "an absorbing medium");
        if (const Json* a = find(v, "absorbance"))
            m.absorbance = r.spectrum(*a, w.child("absorbance"), SpectrumKind::Absorbance);
        if (const Json* d = find(v, "dyes")) {
            const Where dw = w.child("dyes");
            if (!d->is_array() || d->empty())
                failInput(dw, "expected a non-empty list of {{\"absorptivity\": spectrum, \"concentration\": c}}, "
                              "got {}",
                          describe(*d));
            for (size_t i = 0; i < d->size(); ++i) {
                const Where iw = dw.index(i);
                const Json& e = (*d)[i];
                asObject(e, iw);
                checkKeys(e, iw, {"absorptivity", "concentration"}, "a dye");
                Material::Dye dye;
                dye.absorptivity = r.spectrum(require(e, iw, "absorptivity", "a molar absorptivity spectrum, L·mol⁻¹·cm⁻¹"),
                                              iw.child("absorptivity"), SpectrumKind::Absorbance);
                dye.concentration = numberIn(require(e, iw, "concentration", "a concentration, mol·L⁻¹"),
                                             iw.child("concentration"), 0, 1e6, false, false);
                m.dyes.push_back(std::move(dye));
            }
        }
    }
    // Nothing reflects: the opaque spectra are zero, so code that reads them sees a black surface.
    for (SceneSpectrum* s : {&m.diffuse, &m.specular}) {
        s->spectrum = Spectrum::makeConstant(0.0);
        s->kind = SpectrumKind::Reflectance;
        s->where = w;
    }
    return m;
}

}  // namespace metamer
