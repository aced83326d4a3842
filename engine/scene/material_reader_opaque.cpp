// Opaque materials (docs/scene-format.md, "Materials"): a Lambertian "diffuse" and a Blinn–Phong
// "specular" with its "gloss", their "textures" (and a normal or bump map), "fluorescence" as an
// excitation/emission pair or a Donaldson matrix, and an "emitted_radiance" (a self-luminous surface). A paint is an opaque material whose body
// reflectance comes from its layers (scene/material_reader_paint.cpp).
// Tests: engine/scene/material_reader_opaque_test.cpp, engine/scene/scene_json_test.cpp
// (FullSceneLoadsWithTheRightValues), engine/scene/scene_donaldson_test.cpp,
// tests/bad_inputs_test.cpp (the donaldson-, texture- and range- cases), tests/textures_test.cpp.
#include "scene/material_readers.h"

#include <cmath>

namespace metamer {

using namespace json_read;

namespace {

// "textures": {"diffuse": T, "specular": T, "normal": T, "bump": {"file": ..., "scale": s}}
// where T is a file name or {"file": ..., "encoding": "auto"|"srgb"|"linear"}.
MaterialTextures readTextures(SceneReader& r, const Json& v, const Where& w) {
    asObject(v, w);
    checkKeys(v, w, {"diffuse", "specular", "normal", "bump"}, "a material's textures");
    if (find(v, "normal") && find(v, "bump"))
        failInput(w.child("bump"), "a material has either a normal map or a bump map, not both");
    MaterialTextures t;
    if (const Json* x = find(v, "diffuse")) t.diffuse = r.textureRef(*x, w.child("diffuse"), TextureRole::Reflectance);
    if (const Json* x = find(v, "specular"))
        t.specular = r.textureRef(*x, w.child("specular"), TextureRole::Reflectance);
    if (const Json* x = find(v, "normal")) t.normal = r.textureRef(*x, w.child("normal"), TextureRole::Normal);
    if (const Json* x = find(v, "bump")) t.normal = r.textureRef(*x, w.child("bump"), TextureRole::Height);
    return t;
}

}  // namespace

Material readOpaqueMaterial(SceneReader& r, Material m, const Json& v, const Where& w) {
    checkKeys(v, w, {"diffuse", "specular", "gloss", "fluorescence", "textures", "layers", "substrate", "surface",
                     "emitted_radiance"});
    if (const Json* t = find(v, "textures")) m.textures = readTextures(r, *t, w.child("textures"));
    if (find(v, "layers")) {
        readPaint(r, m, v, w);
    } else if (const char* k = find(v, "substrate") ? "substrate" : find(v, "surface") ? "surface" : nullptr) {
        failInput(w.child(k), "'{}' belongs to a paint: give the material 'layers' (Kubelka–Munk films), or "
                              "remove it", k);
    } else if (m.textures.diffuse >= 0 && !find(v, "diffuse")) {
        // A diffuse texture is the reflectance; "diffuse" would tint it.
        m.diffuse.spectrum = Spectrum::makeConstant(1.0);
        m.diffuse.kind = SpectrumKind::Reflectance;
        m.diffuse.where = w.child("diffuse");
    } else {
        m.diffuse = r.spectrum(require(v, w, "diffuse", "a spectrum; 0 for none"), w.child("diffuse"),
                               SpectrumKind::Reflectance);
    }
    if (const Json* s = find(v, "specular")) {
        m.specular = r.spectrum(*s, w.child("specular"), SpectrumKind::Reflectance);
    } else if (m.textures.specular >= 0) {
        m.specular.spectrum = Spectrum::makeConstant(1.0);
        m.specular.kind = SpectrumKind::Reflectance;
        m.specular.where = w.child("specular");
    } else {
        m.specular.spectrum = Spectrum::makeConstant(0.0);
        m.specular.kind = SpectrumKind::Reflectance;
        m.specular.where = w.child("specular");
    }
    if (const Json* g = find(v, "gloss"))
        m.gloss = numberIn(*g, w.child("gloss"), 0, 1e6, false, false);
    else if (m.hasSpecular())
        failInput(w.child("gloss"), "missing required key (the Blinn–Phong exponent; required with a specular)");
    if (const Json* f = find(v, "fluorescence")) {
        Where fw = w.child("fluorescence");
        asObject(*f, fw);
        Fluorescence fl;
        if (const Json* mx = find(*f, "matrix")) {
            // A Donaldson matrix holds the excitation, the emission and the yield together.
            for (const char* k : {"excitation", "emission", "quantum_yield"})
                if (find(*f, k))
                    failInput(fw.child(k),
                              "not allowed with 'matrix': a fluorescence is either a Donaldson matrix or an "
                              "excitation/emission pair with a quantum_yield, not both");
            checkKeys(*f, fw, {"matrix", "scale"}, "a Donaldson-matrix fluorescence");
            fl.matrix = r.matrix(*mx, fw.child("matrix"));
            if (const Json* sc = find(*f, "scale"))
                fl.matrix->scale = numberIn(*sc, fw.child("scale"), 0, INFINITY, false, true);
        } else {
            if (find(*f, "scale"))
                failInput(fw.child("scale"),
                          "'scale' goes with 'matrix'; an excitation/emission fluorescence is scaled by its "
                          "quantum_yield");
            checkKeys(*f, fw, {"excitation", "emission", "quantum_yield"}, "an excitation/emission fluorescence",
                      {"matrix"});
            fl.excitation = r.spectrum(require(*f, fw, "excitation", "a spectrum"), fw.child("excitation"),
                                       SpectrumKind::Excitation);
            fl.emission = r.spectrum(require(*f, fw, "emission", "a spectrum"), fw.child("emission"),
                                     SpectrumKind::Emission);
            fl.quantum_yield = numberIn(require(*f, fw, "quantum_yield", "a number in [0, 1]"),
                                        fw.child("quantum_yield"), 0, 1, false, false);
        }
        m.fluorescence = std::move(fl);
    }
    if (const Json* e = find(v, "emitted_radiance")) {
        // "emitted_radiance": {"spectrum": S, "scale": k}, as a light's: L_e = S × k, W·sr⁻¹·m⁻²·nm⁻¹.
        const Where ew = w.child("emitted_radiance");
        asObject(*e, ew);
        checkKeys(*e, ew, {"spectrum", "scale"}, "an emitted radiance");
        Material::Emitter emitter;
        emitter.where = ew;
        emitter.spectrum = r.spectrum(require(*e, ew, "spectrum", "a spectrum, W·sr⁻¹·m⁻²·nm⁻¹ × scale"),
                                      ew.child("spectrum"), SpectrumKind::Light);
        if (const Json* k = find(*e, "scale")) emitter.scale = numberIn(*k, ew.child("scale"), 0, INFINITY, false, true);
        m.emitter = std::move(emitter);
    }
    return m;
}

}  // namespace metamer
