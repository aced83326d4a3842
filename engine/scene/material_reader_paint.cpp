// Paints and coatings (docs/scene-format.md, "Paints and coatings"): Kubelka–Munk "layers" (each
// a film of "pigments" or of its own K and S, with a "thickness" and an optional "thickness_map"),
// the "substrate" beneath them and the "surface" for Saunderson's correction. The paint is an
// opaque material (scene/material_reader_opaque.cpp) whose body reflectance the layers give.
// Tests: engine/scene/material_reader_paint_test.cpp, tests/paints_test.cpp,
// tests/bad_inputs_test.cpp (the paint- cases).
#include "scene/material_readers.h"

#include <cmath>
#include <tuple>

namespace metamer {

using namespace json_read;

namespace {

Material::Paint::Pigment readPigment(SceneReader& r, const Json& v, const Where& w) {
    asObject(v, w);
    Material::Paint::Pigment p;
    p.where = w;
    if (const Json* n = find(v, "pigment")) {
        checkKeys(v, w, {"pigment", "concentration"}, "a library pigment", {"k", "s"});
        p.name = string(*n, w.child("pigment"));
        const Where nw = w.child("pigment");
        if (!r.library().contains(p.name + "_k") || !r.library().contains(p.name + "_s")) {
            std::string known;
            for (const std::string& s : r.library().names())
                if (s.size() > 2 && s.compare(s.size() - 2, 2, "_k") == 0 && r.library().contains(s.substr(0, s.size() - 2) + "_s"))
                    known += (known.empty() ? "" : ", ") + s.substr(0, s.size() - 2);
            failInput(nw, "unknown pigment '{}': a library pigment is a pair of spectra NAME_k and NAME_s "
                          "(absorption and scattering per unit concentration, m⁻¹); the library has {}",
                      p.name, known.empty() ? "none" : known);
        }
        p.k = r.spectrum(Json(p.name + "_k"), nw, SpectrumKind::KubelkaMunk);
        p.s = r.spectrum(Json(p.name + "_s"), nw, SpectrumKind::KubelkaMunk);
    } else {
        checkKeys(v, w, {"k", "s", "concentration"}, "a pigment given by its spectra");
        p.k = r.spectrum(require(v, w, "k", "the pigment's absorption per unit concentration, m⁻¹ (or \"pigment\": NAME)"),
                         w.child("k"), SpectrumKind::KubelkaMunk);
        p.s = r.spectrum(require(v, w, "s", "the pigment's scattering per unit concentration, m⁻¹"), w.child("s"),
                         SpectrumKind::KubelkaMunk);
    }
    p.concentration = numberIn(require(v, w, "concentration", "the pigment's concentration cᵢ, ≥ 0"),
                               w.child("concentration"), 0, 1e6, false, false);
    return p;
}

// One Kubelka–Munk film: {"K": spectrum, "S": spectrum, "pigments": [...], "thickness": X,
// "thickness_map": texture}; K and S (m⁻¹) and the pigments' cᵢkᵢ, cᵢsᵢ add up.
Material::Paint::Layer readLayer(SceneReader& r, const Json& v, const Where& w, bool bottom) {
    asObject(v, w);
    checkKeys(v, w, {"K", "S", "pigments", "thickness", "thickness_map"}, "a paint layer");
    Material::Paint::Layer l;
    l.where = w;
    if (const Json* k = find(v, "K")) l.K = r.spectrum(*k, w.child("K"), SpectrumKind::KubelkaMunk);
    if (const Json* s = find(v, "S")) l.S = r.spectrum(*s, w.child("S"), SpectrumKind::KubelkaMunk);
    if (const Json* ps = find(v, "pigments")) {
        const Where pw = w.child("pigments");
        if (!ps->is_array() || ps->empty() || ps->size() > 64)
            failInput(pw, "expected a list of 1 … 64 pigments, each {{\"pigment\": NAME, \"concentration\": c}} or "
                          "{{\"k\": ..., \"s\": ..., \"concentration\": c}}; got {}",
                      describe(*ps));
        for (size_t i = 0; i < ps->size(); ++i) l.pigments.push_back(readPigment(r, (*ps)[i], pw.index(i)));
    }
    if (!l.K && !l.S && l.pigments.empty())
        failInput(w, "a layer needs 'pigments', or its own 'K' and 'S' (Kubelka–Munk absorption and scattering, "
                     "m⁻¹)");
    const Json& x = require(v, w, "thickness", "the layer's thickness in metres, or \"opaque\"");
    const Where xw = w.child("thickness");
    if (x.is_string()) {
        if (x.get<std::string>() != "opaque")
            failInput(xw, "expected a thickness in metres or \"opaque\", got \"{}\"", x.get<std::string>());
        if (!bottom)
            failInput(xw, "only the bottom layer may be opaque: an opaque layer hides the layers beneath it");
        l.thickness_m = INFINITY;
    } else {
        l.thickness_m = numberIn(x, xw, 0, 1e3, true, false, " m");
    }
    if (const Json* t = find(v, "thickness_map")) {
        if (std::isinf(l.thickness_m))
            failInput(w.child("thickness_map"), "an opaque layer has no thickness to vary");
        l.thicknessMap = r.textureRef(*t, w.child("thickness_map"), TextureRole::Scalar);
    }
    return l;
}

// A paint's stack (docs/scene-format.md, "Paints and coatings"): "layers" (bottom first),
// "substrate" (a reflectance or {"material": NAME}) unless the bottom layer is opaque, and an
// optional "surface" ({"ior": n} or {"k1": a, "k2": b}) for Saunderson's correction.
Material::Paint readStack(SceneReader& r, const Json& v, const Where& w) {
    Material::Paint p;
    const Json& layers = *find(v, "layers");
    const Where lw = w.child("layers");
    constexpr size_t kMaxLayers = 64;
    if (!layers.is_array() || layers.empty() || layers.size() > kMaxLayers)
        failInput(lw, "expected a list of 1 … {} layers, bottom first, each {{\"pigments\": [...], \"thickness\": "
                      "X}} or {{\"K\": ..., \"S\": ..., \"thickness\": X}}; got {}",
                  kMaxLayers, describe(layers));
    for (size_t i = 0; i < layers.size(); ++i) {
        p.layers.push_back(readLayer(r, layers[i], lw.index(i), i == 0));
        if (p.layers.back().thicknessMap >= 0 && i > 0)
            for (size_t j = 0; j < i; ++j)
                if (p.layers[j].thicknessMap >= 0)
                    failInput(lw.index(i).child("thickness_map"),
                              "only one layer of a paint may have a thickness map (layer {} has one)", j);
    }
    const Where sw = w.child("substrate");
    p.substrateWhere = sw;
    if (std::isinf(p.layers.front().thickness_m)) {
        if (find(v, "substrate"))
            failInput(sw, "not allowed: the bottom layer is opaque (\"thickness\": \"opaque\"), so nothing "
                          "beneath it shows");
    } else {
        const Json& s = require(v, w, "substrate",
                                "what lies beneath the layers: a reflectance spectrum, or {\"material\": NAME} (an "
                                "earlier material's diffuse reflectance)");
        if (s.is_object() && find(s, "material")) {
            checkKeys(s, sw, {"material"}, "a substrate material");
            const std::string name = string(*find(s, "material"), sw.child("material"));
            for (size_t i = 0; i < r.scene().materials.size(); ++i)
                if (r.scene().materials[i].name == name) p.substrateMaterial = int(i);
            if (p.substrateMaterial < 0)
                failInput(sw.child("material"),
                          "unknown material '{}': a substrate must be a material defined before this one", name);
            const Material& under = r.scene().materials[size_t(p.substrateMaterial)];
            if (under.isTransparent())
                failInput(sw.child("material"), "material '{}' is transparent: it has no diffuse reflectance", name);
            if (under.textures.diffuse >= 0 || (under.paint && under.paint->thicknessMap() >= 0))
                failInput(sw.child("material"),
                          "material '{}' varies across its surface (a texture or a thickness map): a substrate "
                          "is one reflectance spectrum",
                          name);
        } else {
            p.substrate = r.spectrum(s, sw, SpectrumKind::Reflectance);
        }
    }
    if (const Json* s = find(v, "surface")) {
        const Where fw = w.child("surface");
        asObject(*s, fw);
        Material::Paint::Surface surface;
        surface.where = fw;
        if (const Json* n = find(*s, "ior")) {
            checkKeys(*s, fw, {"ior"}, "a paint's surface given by its refractive index", {"k1", "k2"});
            std::tie(surface.ior, surface.iorSource) = r.refractiveIndex(*n, fw.child("ior"));
        } else {
            checkKeys(*s, fw, {"k1", "k2"}, "a paint's surface: {\"ior\": n} or {\"k1\": a, \"k2\": b}");
            surface.k1 = numberIn(require(*s, fw, "k1", "the surface's external (specular) reflectance, 0 … 1"),
                                  fw.child("k1"), 0, 1, false, true);
            surface.k2 = numberIn(require(*s, fw, "k2", "the surface's internal diffuse reflectance, 0 … 1"),
                                  fw.child("k2"), 0, 1, false, true);
        }
        p.surface = std::move(surface);
    }
    return p;
}

}  // namespace

void readPaint(SceneReader& r, Material& m, const Json& v, const Where& w) {
    // A paint: its layers' Kubelka–Munk reflectance is the body reflectance, so a diffuse
    // spectrum or texture beside them would be a second, contradicting one.
    if (find(v, "diffuse"))
        failInput(w.child("diffuse"),
                  "not allowed beside 'layers': the layers' Kubelka–Munk reflectance is the material's body "
                  "(diffuse) reflectance");
    if (m.textures.diffuse >= 0)
        failInput(w.child("textures").child("diffuse"),
                  "not allowed with 'layers': a paint's reflectance comes from its layers (vary a layer's "
                  "thickness with its \"thickness_map\")");
    m.paint = readStack(r, v, w);
    m.diffuse.spectrum = Spectrum::makeConstant(1.0);
    m.diffuse.kind = SpectrumKind::Reflectance;
    m.diffuse.where = w.child("layers");
}

}  // namespace metamer
