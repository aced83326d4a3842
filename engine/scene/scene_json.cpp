#include "scene/scene_json.h"
#include "core/file_reads.h"

#include "core/json.h"
#include "scene/json_values.h"
#include "io/spectral_exr.h"
#include "scene/gltf_material.h"
#include "scene/gltf_mesh.h"
#include "scene/overrides.h"
#include "scene/readable_paths.h"
#include "scene/shapes.h"
#include "scene/texture.h"
#include "spectral/csv.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace metamer {

namespace {

using namespace json_read;

// ---------------------------------------------------------------------------------------------

class Loader {
public:
    Loader(const SpectrumLibrary& lib, const fs::path& file, const LoadOptions& options)
        : lib_(lib),
          file_(file),
          dir_(file.parent_path()),
          readable_(ReadablePaths::forScene(file, lib.root(), options.allowOutsidePaths)),
          renderGrid_(options.grid) {}

    Scene load(const Json& doc) {
        Where root{file_.string()};
        asObject(doc, root);
        checkKeys(doc, root, {"description", "grid", "camera", "lights", "materials", "objects", "output"});
        scene_.file = file_;
        if (const Json* d = find(doc, "description")) string(*d, root.child("description"));
        if (const Json* g = find(doc, "grid")) readGrid(*g, root.child("grid"));
        if (const Json* o = find(doc, "output")) readOutput(*o, root.child("output"));
        readCamera(require(doc, root, "camera", "an object: projection, position, target, ..."),
                   root.child("camera"));
        if (const Json* l = find(doc, "lights")) {
            const Json& lights = asArray(*l, root.child("lights"));
            for (size_t i = 0; i < lights.size(); ++i) readLight(lights[i], root.child("lights").index(i));
        }
        if (const Json* m = find(doc, "materials")) {
            Where mw = root.child("materials");
            const Json& materials = asObject(*m, mw);
            for (auto it = materials.begin(); it != materials.end(); ++it)
                readMaterial(it.key(), it.value(), mw.child(it.key()));
        }
        used_.assign(scene_.materials.size(), false);
        // A paint's substrate material is used through the paint.
        for (const Material& m : scene_.materials)
            if (m.paint && m.paint->substrateMaterial >= 0) used_[size_t(m.paint->substrateMaterial)] = true;
        declaredMaterials_ = scene_.materials.size();
        if (const Json* o = find(doc, "objects")) {
            const Json& objects = asArray(*o, root.child("objects"));
            for (size_t i = 0; i < objects.size(); ++i) readObject(objects[i], root.child("objects").index(i));
        }
        if (scene_.lights.empty()) warn(root.child("lights"), "the scene has no lights; it will render black");
        if (scene_.meshes.empty()) warn(root.child("objects"), "the scene has no objects");
        for (size_t i = 0; i < declaredMaterials_; ++i)
            if (!used_[i]) warn(root.child("materials").child(scene_.materials[i].name), "material is not used by any object");
        return std::move(scene_);
    }

private:
    void readGrid(const Json& v, const Where& w) {
        asObject(v, w);
        checkKeys(v, w, {"start_nm", "end_nm", "step_nm", "resample"});
        Grid g;
        g.start_nm = number(require(v, w, "start_nm", "a wavelength in nm"), w.child("start_nm"));
        g.end_nm = number(require(v, w, "end_nm", "a wavelength in nm"), w.child("end_nm"));
        g.step_nm = number(require(v, w, "step_nm", "a step in nm"), w.child("step_nm"));
        if (const Json* r = find(v, "resample"))
            g.resampling = parseResampling(string(*r, w.child("resample")), w.child("resample"));
        g.validate(w);
        scene_.grid = g;
    }

    // Names (detector, adaptation, display) are checked by the display path, which knows them.
    void readOutput(const Json& v, const Where& w) {
        asObject(v, w);
        checkKeys(v, w, {"detector", "adaptation", "display", "bits", "integration", "xyz", "write", "format"});
        OutputSettings& o = scene_.output;
        o.where = w;
        if (const Json* d = find(v, "detector")) o.detector = detector(string(*d, w.child("detector")), w.child("detector"));
        if (const Json* a = find(v, "adaptation")) o.adaptation = string(*a, w.child("adaptation"));
        if (const Json* d = find(v, "display")) o.display = string(*d, w.child("display"));
        if (const Json* b = find(v, "bits")) {
            o.bits = integerIn(*b, w.child("bits"), 8, 16);
            if (*o.bits != 8 && *o.bits != 16) failInput(w.child("bits"), "must be 8 or 16, got {}", *o.bits);
        }
        if (const Json* i = find(v, "integration"))
            o.integration = choice(*i, w.child("integration"), {"riemann", "trapezoid", "astm-e308"});
        if (const Json* x = find(v, "xyz")) o.xyz = choice(*x, w.child("xyz"), {"relative", "absolute"});
        if (const Json* wr = find(v, "write")) {
            const Json& list = asArray(*wr, w.child("write"));
            o.write.emplace();
            for (size_t i = 0; i < list.size(); ++i)
                o.write->push_back(choice(list[i], w.child("write").index(i), {"cube", "png", "xyz", "responses"}));
        }
        // The container names are checked with the render's (render/cube_formats.h, parseCubeFormats).
        if (const Json* f = find(v, "format")) {
            const Json& list = asArray(*f, w.child("format"));
            o.format.emplace();
            for (size_t i = 0; i < list.size(); ++i) o.format->push_back(string(list[i], w.child("format").index(i)));
        }
    }

    void readCamera(const Json& v, const Where& w) {
        asObject(v, w);
        Camera& c = scene_.camera;
        std::string projection = "perspective";
        if (const Json* p = find(v, "projection"))
            projection = choice(*p, w.child("projection"), {"perspective", "orthographic"});
        std::vector<std::string> common = {"projection", "position", "target", "up", "width", "height"};
        std::vector<std::string> persp = common, ortho = common;
        persp.push_back("fov_y_deg");
        ortho.push_back("height_m");
        bool isPersp = projection == "perspective";
        checkKeys(v, w, isPersp ? persp : ortho, fmt::format("{} {} camera", isPersp ? "a" : "an", projection),
                  {isPersp ? "height_m" : "fov_y_deg"});
        c.position = vector<3>(require(v, w, "position", "[x, y, z] in metres"), w.child("position"));
        c.target = vector<3>(require(v, w, "target", "[x, y, z] in metres"), w.child("target"));
        if (const Json* u = find(v, "up")) c.up = nonZeroDirection(*u, w.child("up"));
        glm::dvec3 view = c.target - c.position;
        if (!std::isfinite(glm::length(view)))
            failInput(w.child("target"), "the target is too far from the camera position (the distance overflows)");
        if (!(glm::length(view) > 0.0)) failInput(w.child("target"), "the target equals the camera position");
        if (glm::length(glm::cross(glm::normalize(view), glm::normalize(c.up))) < 1e-6)
            failInput(w.child("up"), "up is parallel to the view direction (target - position)");
        if (const Json* x = find(v, "width")) c.width = integerIn(*x, w.child("width"), 1, 16384);
        if (const Json* x = find(v, "height")) c.height = integerIn(*x, w.child("height"), 1, 16384);
        if (isPersp) {
            c.projection = Camera::Projection::Perspective;
            if (const Json* f = find(v, "fov_y_deg"))
                c.fov_y_deg = numberIn(*f, w.child("fov_y_deg"), 0, 180, true, true, "°");
        } else {
            c.projection = Camera::Projection::Orthographic;
            c.height_m = numberIn(require(v, w, "height_m", "the view height in metres"), w.child("height_m"), 0,
                                  INFINITY, true, true, " m");
        }
    }

    void readLight(const Json& v, const Where& w) {
        asObject(v, w);
        Light l;
        l.name = w.key;
        std::string type = choice(require(v, w, "type", "ambient, directional, point or hemisphere"), w.child("type"),
                                  {"ambient", "directional", "point", "hemisphere"});
        if (type == "ambient") {
            l.type = Light::Type::Ambient;
            checkKeys(v, w, {"type", "spectrum", "scale"}, "an ambient light", {"direction", "position", "up", "shadows"});
        } else if (type == "directional") {
            l.type = Light::Type::Directional;
            checkKeys(v, w, {"type", "direction", "spectrum", "scale", "shadows"}, "a directional light",
                      {"position", "up"});
            l.direction = nonZeroDirection(require(v, w, "direction", "[x, y, z], the way the light travels"),
                                           w.child("direction"));
        } else if (type == "point") {
            l.type = Light::Type::Point;
            checkKeys(v, w, {"type", "position", "spectrum", "scale", "shadows"}, "a point light", {"direction", "up"});
            l.position = vector<3>(require(v, w, "position", "[x, y, z] in metres"), w.child("position"));
        } else {
            l.type = Light::Type::Hemisphere;
            checkKeys(v, w, {"type", "up", "spectrum", "scale"}, "a hemisphere light", {"direction", "position", "shadows"});
            l.up = nonZeroDirection(require(v, w, "up", "[x, y, z], towards the middle of the hemisphere it shines from"),
                                    w.child("up"));
        }
        if (const Json* s = find(v, "shadows")) {
            if (!s->is_boolean()) failInput(w.child("shadows"), "expected true or false, got {}", describe(*s));
            l.shadows = s->get<bool>();
        }
        l.spectrum = spectrum(require(v, w, "spectrum", "a spectrum"), w.child("spectrum"), SpectrumKind::Light);
        if (const Json* s = find(v, "scale")) l.scale = numberIn(*s, w.child("scale"), 0, INFINITY, false, true);
        scene_.lights.push_back(std::move(l));
    }

    void readMaterial(const std::string& name, const Json& v, const Where& w) {
        if (name.empty()) failInput(w, "a material name must not be empty");
        if (name.find('.') != std::string::npos)
            failInput(w, "a material name must not contain '.' (key paths use it)");
        asObject(v, w);
        Material m;
        m.name = name;
        if (find(v, "transmittance") || find(v, "absorbance") || find(v, "dyes") || find(v, "slab")) {
            scene_.materials.push_back(readTransparent(std::move(m), v, w));
            return;
        }
        checkKeys(v, w, {"diffuse", "specular", "gloss", "fluorescence", "textures", "layers", "substrate", "surface"});
        if (const Json* t = find(v, "textures")) m.textures = readTextures(*t, w.child("textures"));
        if (find(v, "layers")) {
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
            m.paint = readPaint(v, w);
            m.diffuse.spectrum = Spectrum::makeConstant(1.0);
            m.diffuse.kind = SpectrumKind::Reflectance;
            m.diffuse.where = w.child("layers");
        } else if (const char* k = find(v, "substrate") ? "substrate" : find(v, "surface") ? "surface" : nullptr) {
            failInput(w.child(k), "'{}' belongs to a paint: give the material 'layers' (Kubelka–Munk films), or "
                                  "remove it", k);
        } else if (m.textures.diffuse >= 0 && !find(v, "diffuse")) {
            // A diffuse texture is the reflectance; "diffuse" would tint it.
            m.diffuse.spectrum = Spectrum::makeConstant(1.0);
            m.diffuse.kind = SpectrumKind::Reflectance;
            m.diffuse.where = w.child("diffuse");
        } else {
            m.diffuse = spectrum(require(v, w, "diffuse", "a spectrum; 0 for none"), w.child("diffuse"),
                                 SpectrumKind::Reflectance);
        }
        if (const Json* s = find(v, "specular")) {
            m.specular = spectrum(*s, w.child("specular"), SpectrumKind::Reflectance);
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
                fl.matrix = matrix(*mx, fw.child("matrix"));
                if (const Json* sc = find(*f, "scale"))
                    fl.matrix->scale = numberIn(*sc, fw.child("scale"), 0, INFINITY, false, true);
            } else {
                if (find(*f, "scale"))
                    failInput(fw.child("scale"),
                              "'scale' goes with 'matrix'; an excitation/emission fluorescence is scaled by its "
                              "quantum_yield");
                checkKeys(*f, fw, {"excitation", "emission", "quantum_yield"}, "an excitation/emission fluorescence",
                          {"matrix"});
                fl.excitation = spectrum(require(*f, fw, "excitation", "a spectrum"), fw.child("excitation"),
                                         SpectrumKind::Excitation);
                fl.emission = spectrum(require(*f, fw, "emission", "a spectrum"), fw.child("emission"),
                                       SpectrumKind::Emission);
                fl.quantum_yield = numberIn(require(*f, fw, "quantum_yield", "a number in [0, 1]"),
                                            fw.child("quantum_yield"), 0, 1, false, false);
            }
            m.fluorescence = std::move(fl);
        }
        scene_.materials.push_back(std::move(m));
    }

    // A transparent material (docs/scene-format.md, "Transparent materials"): a thin sheet
    // {"transmittance": T} or an absorbing medium {"absorbance": a, "dyes": [{"absorptivity": ε,
    // "concentration": c}, …]} (either or both of a and dyes). It reflects nothing: the opaque
    // material's keys are refused by name, so that a user does not believe a glass reflects.
    Material readTransparent(Material m, const Json& v, const Where& w) {
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
            m.slab = readSlab(*find(v, "slab"), w.child("slab"));
        } else if (sheet) {
            for (const char* k : {"absorbance", "dyes"})
                if (find(v, k))
                    failInput(w.child(k),
                              "not allowed with 'transmittance': a material is either a thin sheet (a transmittance "
                              "per crossing) or an absorbing medium (an absorbance per metre inside a closed mesh)");
            checkKeys(v, w, {"transmittance"}, "a filter (a thin sheet)");
            m.transmittance = spectrum(*find(v, "transmittance"), w.child("transmittance"), SpectrumKind::Transmittance);
        } else {
            checkKeys(v, w, {"absorbance", "dyes"}, "an absorbing medium");
            if (const Json* a = find(v, "absorbance"))
                m.absorbance = spectrum(*a, w.child("absorbance"), SpectrumKind::Absorbance);
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
                    dye.absorptivity = spectrum(require(e, iw, "absorptivity", "a molar absorptivity spectrum, L·mol⁻¹·cm⁻¹"),
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

    // A paint (docs/scene-format.md, "Paints and coatings"): "layers" (bottom first), "substrate"
    // (a reflectance or {"material": NAME}) unless the bottom layer is opaque, and an optional
    // "surface" ({"ior": n} or {"k1": a, "k2": b}) for Saunderson's correction.
    Material::Paint readPaint(const Json& v, const Where& w) {
        Material::Paint p;
        const Json& layers = *find(v, "layers");
        const Where lw = w.child("layers");
        constexpr size_t kMaxLayers = 64;
        if (!layers.is_array() || layers.empty() || layers.size() > kMaxLayers)
            failInput(lw, "expected a list of 1 … {} layers, bottom first, each {{\"pigments\": [...], \"thickness\": "
                          "X}} or {{\"K\": ..., \"S\": ..., \"thickness\": X}}; got {}",
                      kMaxLayers, describe(layers));
        for (size_t i = 0; i < layers.size(); ++i) {
            p.layers.push_back(readLayer(layers[i], lw.index(i), i == 0));
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
                for (size_t i = 0; i < scene_.materials.size(); ++i)
                    if (scene_.materials[i].name == name) p.substrateMaterial = int(i);
                if (p.substrateMaterial < 0)
                    failInput(sw.child("material"),
                              "unknown material '{}': a substrate must be a material defined before this one", name);
                const Material& under = scene_.materials[size_t(p.substrateMaterial)];
                if (under.isTransparent())
                    failInput(sw.child("material"), "material '{}' is transparent: it has no diffuse reflectance", name);
                if (under.textures.diffuse >= 0 || (under.paint && under.paint->thicknessMap() >= 0))
                    failInput(sw.child("material"),
                              "material '{}' varies across its surface (a texture or a thickness map): a substrate "
                              "is one reflectance spectrum",
                              name);
            } else {
                p.substrate = spectrum(s, sw, SpectrumKind::Reflectance);
            }
        }
        if (const Json* s = find(v, "surface")) {
            const Where fw = w.child("surface");
            asObject(*s, fw);
            Material::Paint::Surface surface;
            surface.where = fw;
            if (const Json* n = find(*s, "ior")) {
                checkKeys(*s, fw, {"ior"}, "a paint's surface given by its refractive index", {"k1", "k2"});
                std::tie(surface.ior, surface.iorSource) = refractiveIndex(*n, fw.child("ior"));
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

    // One Kubelka–Munk film: {"K": spectrum, "S": spectrum, "pigments": [...], "thickness": X,
    // "thickness_map": texture}; K and S (m⁻¹) and the pigments' cᵢkᵢ, cᵢsᵢ add up.
    Material::Paint::Layer readLayer(const Json& v, const Where& w, bool bottom) {
        asObject(v, w);
        checkKeys(v, w, {"K", "S", "pigments", "thickness", "thickness_map"}, "a paint layer");
        Material::Paint::Layer l;
        l.where = w;
        if (const Json* k = find(v, "K")) l.K = spectrum(*k, w.child("K"), SpectrumKind::KubelkaMunk);
        if (const Json* s = find(v, "S")) l.S = spectrum(*s, w.child("S"), SpectrumKind::KubelkaMunk);
        if (const Json* ps = find(v, "pigments")) {
            const Where pw = w.child("pigments");
            if (!ps->is_array() || ps->empty() || ps->size() > 64)
                failInput(pw, "expected a list of 1 … 64 pigments, each {{\"pigment\": NAME, \"concentration\": c}} or "
                              "{{\"k\": ..., \"s\": ..., \"concentration\": c}}; got {}",
                          describe(*ps));
            for (size_t i = 0; i < ps->size(); ++i) l.pigments.push_back(readPigment((*ps)[i], pw.index(i)));
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
            l.thicknessMap = textureRef(*t, w.child("thickness_map"), TextureRole::Scalar);
        }
        return l;
    }

    Material::Paint::Pigment readPigment(const Json& v, const Where& w) {
        asObject(v, w);
        Material::Paint::Pigment p;
        p.where = w;
        if (const Json* n = find(v, "pigment")) {
            checkKeys(v, w, {"pigment", "concentration"}, "a library pigment", {"k", "s"});
            p.name = string(*n, w.child("pigment"));
            const Where nw = w.child("pigment");
            if (!lib_.contains(p.name + "_k") || !lib_.contains(p.name + "_s")) {
                std::string known;
                for (const std::string& s : lib_.names())
                    if (s.size() > 2 && s.compare(s.size() - 2, 2, "_k") == 0 && lib_.contains(s.substr(0, s.size() - 2) + "_s"))
                        known += (known.empty() ? "" : ", ") + s.substr(0, s.size() - 2);
                failInput(nw, "unknown pigment '{}': a library pigment is a pair of spectra NAME_k and NAME_s "
                              "(absorption and scattering per unit concentration, m⁻¹); the library has {}",
                          p.name, known.empty() ? "none" : known);
            }
            p.k = spectrum(Json(p.name + "_k"), nw, SpectrumKind::KubelkaMunk);
            p.s = spectrum(Json(p.name + "_s"), nw, SpectrumKind::KubelkaMunk);
        } else {
            checkKeys(v, w, {"k", "s", "concentration"}, "a pigment given by its spectra");
            p.k = spectrum(require(v, w, "k", "the pigment's absorption per unit concentration, m⁻¹ (or \"pigment\": NAME)"),
                           w.child("k"), SpectrumKind::KubelkaMunk);
            p.s = spectrum(require(v, w, "s", "the pigment's scattering per unit concentration, m⁻¹"), w.child("s"),
                           SpectrumKind::KubelkaMunk);
        }
        p.concentration = numberIn(require(v, w, "concentration", "the pigment's concentration cᵢ, ≥ 0"),
                                   w.child("concentration"), 0, 1e6, false, false);
        return p;
    }

    // "slab": {"ior": n, "thickness": d, "absorbance": a}: n a number, "N-BK7", {"sellmeier": {"B":
    // [...], "C": [...]}}, {"cauchy": {"A": a, "B": b, "C": c}} or a table {"wavelengths_nm": [...],
    // "values": [...]} (λ in µm for the formulas' coefficients, as glass catalogues give them).
    Material::Slab readSlab(const Json& v, const Where& w) {
        asObject(v, w);
        checkKeys(v, w, {"ior", "thickness", "absorbance"}, "a slab");
        Material::Slab slab;
        slab.thickness_m = numberIn(require(v, w, "thickness", "the slab's thickness in metres"), w.child("thickness"), 0,
                                    INFINITY, true, true, " m");
        if (const Json* a = find(v, "absorbance")) slab.absorbance = spectrum(*a, w.child("absorbance"), SpectrumKind::Absorbance);
        slab.iorWhere = w.child("ior");
        const Json& n = require(v, w, "ior", "a refractive index: a number, \"N-BK7\", {\"sellmeier\": ...}, "
                                                "{\"cauchy\": ...} or a table");
        std::tie(slab.ior, slab.iorSource) = refractiveIndex(n, slab.iorWhere);
        return slab;
    }

    // A refractive index n(λ) (docs/scene-format.md, the slab's "ior"): a number (1 … 5), "N-BK7",
    // {"sellmeier": {"B": [...], "C": [...]}}, {"cauchy": {"A": a, "B": b, "C": c}} or a table
    // {"wavelengths_nm": [...], "values": [...]} (λ in µm for the formulas' coefficients, as glass
    // catalogues give them), and how the scene gave it, for messages.
    std::pair<RefractiveIndex, std::string> refractiveIndex(const Json& n, const Where& iw) {
        RefractiveIndex ior;
        std::string source;
        constexpr const char* kForms =
            "a number (1 … 5), \"N-BK7\", {\"sellmeier\": {\"B\": [...], \"C\": [...]}}, {\"cauchy\": {\"A\": a, \"B\": b, "
            "\"C\": c}} or {\"wavelengths_nm\": [...], \"values\": [...]}";
        if (n.is_number()) {
            ior.kind = RefractiveIndex::Kind::Constant;
            ior.constant = numberIn(n, iw, 1, 5, false, false);
            source = fmt::format("{:g}", ior.constant);
        } else if (n.is_string()) {
            if (n.get<std::string>() != "N-BK7") failInput(iw, "unknown glass '{}'; expected {}", n.get<std::string>(), kForms);
            ior = nbk7();
            source = "N-BK7";
        } else if (n.is_object() && find(n, "sellmeier")) {
            checkKeys(n, iw, {"sellmeier"}, "a Sellmeier index");
            const Where sw = iw.child("sellmeier");
            const Json& f = *find(n, "sellmeier");
            asObject(f, sw);
            checkKeys(f, sw, {"B", "C"}, "Sellmeier coefficients");
            ior.kind = RefractiveIndex::Kind::Sellmeier;
            ior.b = numbers(require(f, sw, "B", "the coefficients B₁ … (dimensionless)"), sw.child("B"));
            ior.c = numbers(require(f, sw, "C", "the coefficients C₁ … in µm²"), sw.child("C"));
            if (ior.b.size() != ior.c.size() || ior.b.empty())
                failInput(sw, "expected as many B as C coefficients (at least one), got {} and {}", ior.b.size(),
                          ior.c.size());
            source = "sellmeier";
        } else if (n.is_object() && find(n, "cauchy")) {
            checkKeys(n, iw, {"cauchy"}, "a Cauchy index");
            const Where cw = iw.child("cauchy");
            const Json& f = *find(n, "cauchy");
            asObject(f, cw);
            checkKeys(f, cw, {"A", "B", "C"}, "Cauchy coefficients");
            ior.kind = RefractiveIndex::Kind::Cauchy;
            ior.b = {numberIn(require(f, cw, "A", "n at infinite wavelength"), cw.child("A"), 1, 5, false, false),
                          find(f, "B") ? number(*find(f, "B"), cw.child("B")) : 0.0,
                          find(f, "C") ? number(*find(f, "C"), cw.child("C")) : 0.0};
            source = "cauchy";
        } else if (n.is_object() && find(n, "wavelengths_nm")) {
            checkKeys(n, iw, {"wavelengths_nm", "values"}, "a refractive-index table");
            ior.kind = RefractiveIndex::Kind::Table;
            ior.wavelengths_nm = numbers(require(n, iw, "wavelengths_nm", "increasing wavelengths, nm"), iw.child("wavelengths_nm"));
            ior.values = numbers(require(n, iw, "values", "n at each wavelength"), iw.child("values"));
            if (ior.values.size() != ior.wavelengths_nm.size() || ior.values.empty())
                failInput(iw, "expected as many values as wavelengths (at least one), got {} and {}",
                          ior.values.size(), ior.wavelengths_nm.size());
            for (size_t i = 1; i < ior.wavelengths_nm.size(); ++i)
                if (!(ior.wavelengths_nm[i] > ior.wavelengths_nm[i - 1]))
                    failInput(iw.child("wavelengths_nm"), "wavelengths must increase ({:g} after {:g})",
                              ior.wavelengths_nm[i], ior.wavelengths_nm[i - 1]);
            source = "table";
        } else {
            failInput(iw, "expected {}, got {}", kForms, describe(n));
        }
        return {ior, source};
    }

    std::vector<double> numbers(const Json& v, const Where& w) {
        if (!v.is_array() || v.empty()) failInput(w, "expected a non-empty array of numbers, got {}", describe(v));
        std::vector<double> out;
        for (size_t i = 0; i < v.size(); ++i) out.push_back(number(v[i], w.index(i)));
        return out;
    }

    // "textures": {"diffuse": T, "specular": T, "normal": T, "bump": {"file": ..., "scale": s}}
    // where T is a file name or {"file": ..., "encoding": "auto"|"srgb"|"linear"}.
    MaterialTextures readTextures(const Json& v, const Where& w) {
        asObject(v, w);
        checkKeys(v, w, {"diffuse", "specular", "normal", "bump"}, "a material's textures");
        if (find(v, "normal") && find(v, "bump"))
            failInput(w.child("bump"), "a material has either a normal map or a bump map, not both");
        MaterialTextures t;
        if (const Json* x = find(v, "diffuse")) t.diffuse = textureRef(*x, w.child("diffuse"), TextureRole::Reflectance);
        if (const Json* x = find(v, "specular"))
            t.specular = textureRef(*x, w.child("specular"), TextureRole::Reflectance);
        if (const Json* x = find(v, "normal")) t.normal = textureRef(*x, w.child("normal"), TextureRole::Normal);
        if (const Json* x = find(v, "bump")) t.normal = textureRef(*x, w.child("bump"), TextureRole::Height);
        return t;
    }

    int textureRef(const Json& v, const Where& w, TextureRole role) {
        std::string given;
        TextureEncoding encoding = TextureEncoding::Auto;
        double scale = 1.0;
        if (v.is_string()) {
            given = v.get<std::string>();
            if (role == TextureRole::Height)
                failInput(w, "expected {{\"file\": \"...\", \"scale\": s}}: a bump map needs its scale (height in "
                             "texel widths per unit value)");
        } else if (v.is_object()) {
            if (role == TextureRole::Height)
                checkKeys(v, w, {"file", "scale"}, "a bump map");
            else if (role == TextureRole::Normal)
                checkKeys(v, w, {"file"}, "a normal map");
            else
                checkKeys(v, w, {"file", "encoding"}, "a texture");
            given = string(require(v, w, "file", "a texture file name"), w.child("file"));
            if (const Json* e = find(v, "encoding")) {
                std::string c = choice(*e, w.child("encoding"), {"auto", "srgb", "linear"});
                encoding = c == "srgb" ? TextureEncoding::Srgb : c == "linear" ? TextureEncoding::Linear : TextureEncoding::Auto;
            }
            if (role == TextureRole::Height)
                scale = numberIn(require(v, w, "scale", "the height, in texel widths, of a value step of 1"),
                                 w.child("scale"), -1e6, 1e6, false, false);
        } else {
            failInput(w, "expected a texture file name or {{\"file\": ...}}, got {}", describe(v));
        }
        Where fw = v.is_object() ? w.child("file") : w;
        if (given.empty()) failInput(fw, "expected a texture file name, got an empty string");
        fs::path path = (dir_ / given).lexically_normal();
        readable_.check(path, fw, "texture file", given);
        for (size_t i = 0; i < textureKeys_.size(); ++i)
            if (textureKeys_[i].path == path && textureKeys_[i].role == role && textureKeys_[i].encoding == encoding &&
                textureKeys_[i].scale == scale)
                return int(i);
        scene_.textures.push_back(loadTexture(path, role, encoding, scale, fw, textureGrid()));
        scene_.textures.back().where = fw;
        textureKeys_.push_back({path, role, encoding, scale});
        return int(scene_.textures.size() - 1);
    }
    struct TextureKey {
        fs::path path;
        TextureRole role;
        TextureEncoding encoding;
        double scale;
    };
    std::vector<TextureKey> textureKeys_;

    // The scene material for a glTF material: one of the scene's own with the same name (an
    // override), else the glTF material converted (scene/gltf_material.h), made once per file and
    // material.
    uint32_t gltfMaterialRef(const GltfModel& model, uint32_t index, const fs::path& path, const Where& w) {
        // glTF's default material when a primitive names none. A reference, not a copy: materials
        // carry their embedded images' bytes, and this runs for every primitive.
        static const GltfMaterial kDefault = [] {
            GltfMaterial d;
            d.name = "gltf-default";
            return d;
        }();
        const GltfMaterial& g = index != kNoGltfMaterial ? model.materials[index] : kDefault;
        for (size_t i = 0; i < declaredMaterials_; ++i)
            if (scene_.materials[i].name == g.name) {
                used_[i] = true;
                return uint32_t(i);
            }
        for (const auto& c : converted_)
            if (c.path == path && c.index == index) return c.material;
        const RgbUpsampler& up = RgbUpsampler::srgb(lib_);
        Where mw = w.child(fmt::format("materials.{}", g.name));
        Material m = materialFromGltf(g, up, mw);
        // An image file of its own is read under the scene's path rules; an embedded one from memory.
        auto load = [&](const GltfImage& image, TextureRole role, TextureEncoding encoding) {
            if (image.isEmbedded())
                return loadTexture(EncodedImage{image.name, image.embedded}, role, encoding, 1.0, mw, textureGrid());
            readable_.check(image.file, w, "texture file", image.name);
            return loadTexture(image.file, role, encoding, 1.0, mw, textureGrid());
        };
        if (g.baseColorTexture) {
            Texture tex = load(*g.baseColorTexture, TextureRole::Reflectance, TextureEncoding::Srgb);
            if (tex.kind == Texture::Kind::Rgb)  // glTF: base colour = factor × texel, in linear RGB
                for (size_t p = 0; p < tex.texels.size(); p += 3)
                    for (int c = 0; c < 3; ++c) tex.texels[p + c] *= float(g.baseColorFactor[c]);
            tex.where = mw;
            scene_.textures.push_back(std::move(tex));
            m.textures.diffuse = int(scene_.textures.size() - 1);
        }
        if (g.normalTexture) {
            Texture tex = load(*g.normalTexture, TextureRole::Normal, TextureEncoding::Auto);
            // normalTexture.scale multiplies the map's x and y before renormalizing.
            for (size_t p = 0; p < tex.texels.size(); p += 3) {
                glm::dvec3 n(tex.texels[p] * g.normalScale, tex.texels[p + 1] * g.normalScale, tex.texels[p + 2]);
                n = glm::length(n) > 0.0 ? glm::normalize(n) : glm::dvec3(0, 0, 1);
                for (int c = 0; c < 3; ++c) tex.texels[p + c] = float(n[c]);
            }
            tex.where = mw;
            scene_.textures.push_back(std::move(tex));
            m.textures.normal = int(scene_.textures.size() - 1);
        }
        scene_.materials.push_back(std::move(m));
        used_.push_back(true);
        uint32_t added = uint32_t(scene_.materials.size() - 1);
        converted_.push_back({path, index, added});
        return added;
    }
    struct ConvertedMaterial {
        fs::path path;
        uint32_t index;
        uint32_t material;
    };
    std::vector<ConvertedMaterial> converted_;
    size_t declaredMaterials_ = 0;  // materials from the scene's "materials" (the rest come from glTF files)

    uint32_t materialRef(const Json& obj, const Where& w) {
        Where mw = w.child("material");
        std::string name = string(require(obj, w, "material", "a material name"), mw);
        std::vector<std::string> names;
        for (const auto& m : scene_.materials) names.push_back(m.name);
        auto it = std::find(names.begin(), names.end(), name);
        if (it == names.end()) {
            std::string near = closestMatch(name, names);
            if (!near.empty()) failInput(mw, "no material '{}'; did you mean '{}'?", name, near);
            if (names.empty()) failInput(mw, "no material '{}': the scene defines no materials", name);
            failInput(mw, "no material '{}'; the materials are {}", name, join(names));
        }
        uint32_t index = static_cast<uint32_t>(it - names.begin());
        used_[index] = true;
        return index;
    }

    void readObject(const Json& v, const Where& w) {
        asObject(v, w);
        const Json* shape = find(v, "shape");
        const Json* mesh = find(v, "mesh");
        if (shape && mesh) failInput(w.child("mesh"), "an object has either \"shape\" or \"mesh\", not both");
        if (!shape && !mesh)
            failInput(w, "expected \"shape\": \"sphere\" or \"quad\", or \"mesh\": a glTF file");
        Mesh out;
        if (mesh) {
            checkKeys(v, w, {"mesh", "material", "translate", "rotate_deg", "scale"}, "a mesh object");
            std::string given = string(*mesh, w.child("mesh"));
            if (given.empty()) failInput(w.child("mesh"), "expected a glTF file name, got an empty string");
            fs::path path = (dir_ / given).lexically_normal();
            readable_.check(path, w.child("mesh"), "mesh file", given);
            // Without "material" the file's own materials are used (each overridable by a scene
            // material of the same name); with it, the whole mesh takes that material.
            const bool ownMaterials = !find(v, "material");
            GltfModel model;
            if (ownMaterials)
                model = loadGltf(path, w.child("mesh"), &readable_);
            else
                out = loadGltfMesh(path, w.child("mesh"), &readable_);
            glm::dvec3 t(0.0), r(0.0), s(1.0);
            if (const Json* x = find(v, "translate")) t = vector<3>(*x, w.child("translate"));
            if (const Json* x = find(v, "rotate_deg")) r = vector<3>(*x, w.child("rotate_deg"));
            if (const Json* x = find(v, "scale")) {
                Where sw = w.child("scale");
                if (x->is_number())
                    s = glm::dvec3(number(*x, sw));
                else if (x->is_array())
                    s = vector<3>(*x, sw);
                else
                    failInput(sw, "expected a number or an array of 3 numbers, got {}", describe(*x));
                if (!(s.x > 0 && s.y > 0 && s.z > 0)) failInput(sw, "scale factors must be > 0");
            }
            if (ownMaterials) {
                for (Mesh& part : model.meshes) {
                    transformMesh(part, objectTransform(t, r, s));
                    part.name = w.key + " (" + given + ")";
                    for (size_t i = 0; i < part.positions.size(); ++i)
                        if (!isFinite(part.positions[i]) || !isFinite(part.normals[i]))
                            failInput(w, "the object's geometry is not finite: its position, size or scale is too "
                                         "large or too small for double precision");
                    part.material = gltfMaterialRef(model, part.material, path, w.child("mesh"));
                    if (scene_.materials[part.material].needsTextureCoordinates() && part.uvs.empty())
                        failInput(w.child("mesh"),
                                  "mesh file '{}': a primitive with material '{}' has textures but no TEXCOORD_0",
                                  given, scene_.materials[part.material].name);
                    part.closed = isClosedOutward(part);
                    requireClosedMedium(part, w);
                    scene_.meshes.push_back(std::move(part));
                }
                return;
            }
            transformMesh(out, objectTransform(t, r, s));
            out.closed = isClosedOutward(out);
            out.name = w.key + " (" + given + ")";
        } else {
            std::string kind = choice(*shape, w.child("shape"), {"sphere", "quad", "box"});
            if (kind == "box") {
                checkKeys(v, w, {"shape", "material", "center", "size"}, "a box",
                          {"radius", "segments", "normal", "up", "translate", "rotate_deg", "scale"});
                glm::dvec3 c = vector<3>(require(v, w, "center", "[x, y, z] in metres"), w.child("center"));
                Where sw = w.child("size");
                glm::dvec3 size = vector<3>(require(v, w, "size", "[x, y, z] edge lengths in metres"), sw);
                if (!(size.x > 0 && size.y > 0 && size.z > 0)) failInput(sw, "edge lengths must be > 0");
                out = makeBox(c, size);
            } else if (kind == "sphere") {
                checkKeys(v, w, {"shape", "material", "center", "radius", "segments"}, "a sphere",
                          {"normal", "size", "up", "translate", "rotate_deg", "scale"});
                glm::dvec3 c = vector<3>(require(v, w, "center", "[x, y, z] in metres"), w.child("center"));
                double r = numberIn(require(v, w, "radius", "metres"), w.child("radius"), 0, INFINITY, true, true, " m");
                int segments = sphereSegmentsFor(scene_.camera, c, r);  // the camera is read first
                if (const Json* x = find(v, "segments"))
                    segments = integerIn(*x, w.child("segments"), kMinSphereSegments, kMaxSphereSegments);
                out = makeSphere(c, r, segments);
            } else {
                checkKeys(v, w, {"shape", "material", "center", "normal", "size", "up"}, "a quad",
                          {"radius", "segments", "translate", "rotate_deg", "scale"});
                glm::dvec3 c = vector<3>(require(v, w, "center", "[x, y, z] in metres"), w.child("center"));
                glm::dvec3 n = nonZeroDirection(require(v, w, "normal", "[x, y, z]"), w.child("normal"));
                Where sw = w.child("size");
                glm::dvec2 size = vector<2>(require(v, w, "size", "[width, height] in metres"), sw);
                if (!(size.x > 0 && size.y > 0)) failInput(sw, "width and height must be > 0");
                std::optional<glm::dvec3> up;
                if (const Json* u = find(v, "up")) {
                    up = nonZeroDirection(*u, w.child("up"));
                    if (!quadAxes(n, up)) failInput(w.child("up"), "up is (nearly) parallel to the normal");
                }
                out = makeQuad(c, n, size, up);
            }
            out.name = w.key;
        }
        // Finite numbers can still make infinite geometry (a centre of 1e308 plus a radius of
        // 1e308), and extreme scales can make the normals 0/0.
        for (size_t i = 0; i < out.positions.size(); ++i)
            if (!isFinite(out.positions[i]) || !isFinite(out.normals[i]))
                failInput(w, "the object's geometry is not finite: its position, size or scale is too large or "
                             "too small for double precision");
        out.material = materialRef(v, w);
        if (scene_.materials[out.material].needsTextureCoordinates() && out.uvs.empty())
            failInput(w.child("material"),
                      "material '{}' has textures but this object has no texture coordinates (spheres have none; use "
                      "a quad or a glTF mesh with TEXCOORD_0)",
                      scene_.materials[out.material].name);
        requireClosedMedium(out, w);
        scene_.meshes.push_back(std::move(out));
    }

    // An absorbing medium fills a volume: the path length inside is measured between the faces a
    // ray enters and leaves by, which needs a closed mesh wound outwards (Mesh::closed).
    void requireClosedMedium(const Mesh& mesh, const Where& w) const {
        const Material& m = scene_.materials[mesh.material];
        if (m.isMedium() && !mesh.closed)
            failInput(w.child("material"),
                      "material '{}' is an absorbing medium, which must fill a closed mesh wound outwards (a box, a "
                      "sphere, or a watertight glTF mesh); this object is open. For a sheet, give the material a "
                      "'transmittance' instead",
                      m.name);
    }

    SceneSpectrum spectrum(const Json& v, const Where& w, SpectrumKind kind) {
        SceneSpectrum s;
        s.kind = kind;
        s.where = w;
        if (v.is_number()) {
            double x = number(v, w);
            if (kind == SpectrumKind::Emission)
                failInput(w, "an emission spectrum must be sampled data (its shape matters), not a constant");
            if (kind == SpectrumKind::Light && x < 0) failInput(w, "a light's spectrum must be ≥ 0, got {:g}", x);
            if (kind == SpectrumKind::Absorbance && x < 0) failInput(w, "an absorbance must be ≥ 0, got {:g}", x);
            if (kind == SpectrumKind::KubelkaMunk && !(x >= 0 && x < 1e12))
                failInput(w, "a Kubelka–Munk coefficient must be within [0, 1e12) per metre, got {:g}", x);
            if ((kind == SpectrumKind::Reflectance || kind == SpectrumKind::Excitation ||
                 kind == SpectrumKind::Transmittance) &&
                (x < 0 || x > 1))
                failInput(w, "a {} must be within [0, 1], got {:g}", kindName(kind), x);
            s.spectrum = Spectrum::makeConstant(x);
        } else if (v.is_string()) {
            std::string name = v.get<std::string>();
            if (name.empty()) failInput(w, "expected a spectrum name, got an empty string");
            if (endsWithCsv(name)) {
                fs::path path = (dir_ / name).lexically_normal();
                readable_.check(path, w, "spectrum file", name);
                requireRegularFile(path, w, "spectrum file");
                try {
                    s.spectrum = readSpectrumCsv(path);
                } catch (const Error& e) {
                    failInput(w, "{}", e.text());
                }
                s.spectrum.source = name;
            } else {
                try {
                    s.spectrum = lib_.get(name, w);
                } catch (const Error& e) {
                    if (e.where().file == w.file && e.where().key == w.key) throw;
                    failInput(w, "library spectrum '{}': {}", name, e.text());
                }
            }
        } else if (v.is_object()) {
            checkKeys(v, w, {"wavelengths_nm", "values"}, "an inline spectrum");
            auto numbers = [&](const char* key) {
                Where kw = w.child(key);
                const Json& a = require(v, w, key, "an array of numbers");
                if (!a.is_array()) failInput(kw, "expected an array of numbers, got {}", describe(a));
                std::vector<double> out;
                for (size_t i = 0; i < a.size(); ++i) out.push_back(number(a[i], kw.index(i)));
                return out;
            };
            s.spectrum.wavelengths_nm = numbers("wavelengths_nm");
            s.spectrum.values = numbers("values");
            s.spectrum.source = "inline";
            s.spectrum.validate(w);
        } else {
            failInput(w,
                      "expected a spectrum (a library name, a .csv path, a number or "
                      "{{\"wavelengths_nm\": [...], \"values\": [...]}}), got {}",
                      describe(v));
        }
        if (!s.spectrum.isConstant()) checkValues(s);
        return s;
    }

    // "matrix": a .csv or .exr file relative to the scene, or a library name (NAME.csv, else
    // NAME.exr, under the spectra library).
    SceneMatrix matrix(const Json& v, const Where& w) {
        if (!v.is_string())
            failInput(w, "expected a Donaldson matrix: a .csv or .exr file, or a library name; got {}", describe(v));
        std::string name = v.get<std::string>();
        if (name.empty()) failInput(w, "expected a Donaldson matrix file name, got an empty string");
        auto endsWith = [&](const char* ext) {
            std::string tail = name.size() >= 4 ? name.substr(name.size() - 4) : "";
            std::transform(tail.begin(), tail.end(), tail.begin(), [](unsigned char c) { return std::tolower(c); });
            return tail == ext;
        };
        bool exr = endsWith(".exr");
        fs::path path;
        std::error_code ec;
        if (exr || endsWith(".csv")) {
            path = (dir_ / name).lexically_normal();
            readable_.check(path, w, "Donaldson matrix file", name);
            requireRegularFile(path, w, "Donaldson matrix file");
        } else {
            fs::path base = (lib_.root() / name).lexically_normal();
            fs::path csv = base.string() + ".csv", exrPath = base.string() + ".exr";
            if (fs::is_regular_file(csv, ec)) {
                path = csv;
            } else if (fs::is_regular_file(exrPath, ec)) {
                path = exrPath;
                exr = true;
            } else {
                failInput(w, "no Donaldson matrix '{}' in the spectra library ({}): neither {}.csv nor {}.exr exists", name,
                          lib_.root().string(), name, name);
            }
            readable_.check(path, w, "Donaldson matrix file", name);
        }
        SceneMatrix m;
        m.where = w;
        try {
            if (exr) {
                BispectralExr read = readBispectralExr(path);
                m.matrix = std::move(read.matrix);
                if (read.reflectiveChannels > 0)
                    warn(w, fmt::format("Donaldson matrix '{}': {} reflective T.<λ>nm channel(s) ignored; the "
                                        "material's reflectance is its 'diffuse'",
                                        name, read.reflectiveChannels));
            } else {
                m.matrix = readBispectralCsv(path);
            }
            m.matrix.validate(Where{path.string()});
        } catch (const Error& e) {
            failInput(w, "{}", e.text());
        }
        m.matrix.source = name;
        return m;
    }

    // Sampled data outside the physical range is suspicious but can be legitimate (noisy
    // measurements), so it is a warning.
    static void checkValues(const SceneSpectrum& s) {
        const auto& vals = s.spectrum.values;
        auto [lo, hi] = std::minmax_element(vals.begin(), vals.end());
        const auto& wl = s.spectrum.wavelengths_nm;
        if (*lo < 0)
            warn(s.where, fmt::format("{} spectrum '{}' is negative ({:g} at {:g} nm)", kindName(s.kind),
                                      s.spectrum.source, *lo, wl[lo - vals.begin()]));
        bool bounded = s.kind == SpectrumKind::Reflectance || s.kind == SpectrumKind::Excitation ||
                       s.kind == SpectrumKind::Transmittance;
        if (bounded && *hi > 1)
            warn(s.where, fmt::format("{} spectrum '{}' exceeds 1 ({:g} at {:g} nm)", kindName(s.kind),
                                      s.spectrum.source, *hi, wl[hi - vals.begin()]));
    }

    // A csv: detector in the scene is a file like any other the scene names: relative to the
    // scene's folder, and subject to the same limits. Other names are checked by the display path.
    std::string detector(const std::string& name, const Where& w) {
        if (name.rfind("csv:", 0) != 0 || name.size() == 4) return name;
        std::string given = name.substr(4);
        fs::path path = (dir_ / given).lexically_normal();
        readable_.check(path, w, "detector file", given);
        return "csv:" + path.string();
    }

    // The grid textures will be resampled to: the job's when it sets one, else the scene's (read
    // before the materials), so an oversized texture is refused before it is decoded.
    const Grid* textureGrid() const { return renderGrid_ ? &*renderGrid_ : &scene_.grid; }

    const SpectrumLibrary& lib_;
    fs::path file_;
    fs::path dir_;
    ReadablePaths readable_;
    std::optional<Grid> renderGrid_;
    Scene scene_;
    std::vector<bool> used_;
};

}  // namespace

Scene loadSceneFromString(const std::string& text, const fs::path& file, const SpectrumLibrary& lib,
                          const std::vector<std::string>& overrides, const LoadOptions& options) {
    std::string name = file.string();
    Json doc = parseJson(text, name);
    if (!doc.is_object()) failInput(Where{name}, "expected a JSON object at the top level, got {}", describe(doc));
    std::vector<Override> applied = applyOverrides(doc, overrides, name);
    try {
        return Loader(lib, file, options).load(doc);
    } catch (const Error& e) {
        // An error in a value that came from --set should say so: the file is not at fault.
        const std::string& key = e.where().key;
        for (auto it = applied.rbegin(); it != applied.rend(); ++it)
            if (key == it->key || key.rfind(it->key + ".", 0) == 0)
                throw Error(e.code(), e.where(), e.message() + " (from --set " + it->text + ")");
        throw;
    }
}

Scene loadScene(const fs::path& file, const SpectrumLibrary& lib, const std::vector<std::string>& overrides,
                const LoadOptions& options) {
    return loadSceneFromString(readWholeFile(file, Where{file.string()}, "scene file"), file, lib, overrides,
                               options);
}

}  // namespace metamer
