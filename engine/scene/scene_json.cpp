// Scene files (docs/scene-format.md): the document's structure — grid, output, camera, lights,
// objects (shapes and glTF meshes, with their materials) — and the choice of each material's model,
// whose reader is a file of its own (scene/material_readers.h). What the readers share, spectra and
// the paths a scene may read among it, is scene/scene_reader.h.
// Tests: engine/scene/scene_json_test.cpp, engine/scene/scene_output_test.cpp,
// engine/scene/bundled_scenes_test.cpp, tests/bad_inputs_test.cpp (tests/bad-inputs/),
// tests/textures_test.cpp.
#include "scene/scene_json.h"

#include "core/file_reads.h"
#include "scene/gltf_material.h"
#include "scene/gltf_mesh.h"
#include "scene/material_readers.h"
#include "scene/overrides.h"
#include "scene/shapes.h"
#include "scene/texture.h"

#include <algorithm>
#include <cmath>

namespace fs = std::filesystem;

namespace metamer {

namespace {

using namespace json_read;

// ---------------------------------------------------------------------------------------------

class Loader {
public:
    Loader(const SpectrumLibrary& lib, const fs::path& file, const LoadOptions& options)
        : reader_(lib, file, options.allowOutsidePaths, options.grid) {}

    Scene load(const Json& doc) {
        Where root{reader_.file().string()};
        asObject(doc, root);
        checkKeys(doc, root, {"description", "grid", "camera", "lights", "materials", "objects", "output", "interreflection"});
        scene().file = reader_.file();
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
        used_.assign(scene().materials.size(), false);
        // A paint's substrate material is used through the paint.
        for (const Material& m : scene().materials)
            if (m.paint && m.paint->substrateMaterial >= 0) used_[size_t(m.paint->substrateMaterial)] = true;
        declaredMaterials_ = scene().materials.size();
        if (const Json* o = find(doc, "objects")) {
            const Json& objects = asArray(*o, root.child("objects"));
            for (size_t i = 0; i < objects.size(); ++i) readObject(objects[i], root.child("objects").index(i));
        }
        if (const Json* i = find(doc, "interreflection")) readInterreflection(*i, root.child("interreflection"));
        if (scene().lights.empty() && !scene().hasEmitters())
            warn(root.child("lights"), "the scene has no lights; it will render black");
        // An emitting surface lights the others only by interreflection.
        if (!scene().interreflection)
            for (const Material& m : scene().materials)
                if (m.emitter)
                    warn(m.emitter->where, "this surface is seen glowing but lights nothing else: the scene has no "
                                           "\"interreflection\"");
        if (scene().meshes.empty()) warn(root.child("objects"), "the scene has no objects");
        for (size_t i = 0; i < declaredMaterials_; ++i)
            if (!used_[i]) warn(root.child("materials").child(scene().materials[i].name), "material is not used by any object");
        return std::move(scene());
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
        scene().grid = g;
    }

    // Names (detector, adaptation, display) are checked by the display path, which knows them.
    // "interreflection": true (the defaults), false (off), or an object of the settings. After the
    // materials: the combinations the solve does not model are refused here, naming both keys.
    void readInterreflection(const Json& v, const Where& w) {
        Interreflection r;
        r.where = w;
        if (v.is_boolean()) {
            if (!v.get<bool>()) return;
        } else {
            asObject(v, w);
            checkKeys(v, w, {"element_size", "tolerance", "max_elements", "refine", "refine_threshold"});
            if (const Json* e = find(v, "element_size"))
                r.elementSize_m = numberIn(*e, w.child("element_size"), 0, 1e6, true, false, "m");
            if (const Json* t = find(v, "tolerance")) r.tolerance = numberIn(*t, w.child("tolerance"), 1e-12, 0.1, false, false);
            if (const Json* m = find(v, "max_elements")) r.maxElements = integerIn(*m, w.child("max_elements"), 1, 50000);
            if (const Json* x = find(v, "refine")) r.refine = integerIn(*x, w.child("refine"), 0, 8);
            if (const Json* x = find(v, "refine_threshold"))
                r.refineThreshold = numberIn(*x, w.child("refine_threshold"), 0, 10, false, false);
        }
        for (const Material& m : scene().materials) {
            const Where mw = Where{reader_.file().string(), "materials"}.child(m.name);
            if (m.isTransparent())
                failInput(w, "not modelled together with the transparent material {} ({}): light through a filter, "
                          "medium or slab does not bounce in this renderer; remove one of the two",
                          m.name, mw.key);
            if (m.fluorescence && m.textures.diffuse >= 0)
                failInput(w, "not modelled together with {}, a fluorescent material with a diffuse texture (its "
                          "re-emission of the indirect light would need the texture at every element); remove one",
                          mw.key);
        }
        scene().interreflection = r;
    }

    void readOutput(const Json& v, const Where& w) {
        asObject(v, w);
        checkKeys(v, w, {"detector", "adaptation", "display", "bits", "integration", "xyz", "write", "format"});
        OutputSettings& o = scene().output;
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
                o.write->push_back(choice(list[i], w.child("write").index(i), {"cube", "png", "xyz", "responses", "reflectance", "illumination",
                                                                         "ids", "depth", "normal"}));  // render/outputs.h
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
        Camera& c = scene().camera;
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
        l.spectrum =
            reader_.spectrum(require(v, w, "spectrum", "a spectrum"), w.child("spectrum"), SpectrumKind::Light);
        if (const Json* s = find(v, "scale")) l.scale = numberIn(*s, w.child("scale"), 0, INFINITY, false, true);
        scene().lights.push_back(std::move(l));
    }

    // The material model is chosen by its keys; each model's reader is a file of its own
    // (scene/material_readers.h).
    void readMaterial(const std::string& name, const Json& v, const Where& w) {
        if (name.empty()) failInput(w, "a material name must not be empty");
        if (name.find('.') != std::string::npos)
            failInput(w, "a material name must not contain '.' (key paths use it)");
        asObject(v, w);
        Material m;
        m.name = name;
        if (find(v, "transmittance") || find(v, "absorbance") || find(v, "dyes") || find(v, "slab"))
            scene().materials.push_back(readTransparentMaterial(reader_, std::move(m), v, w));
        else
            scene().materials.push_back(readOpaqueMaterial(reader_, std::move(m), v, w));
    }

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
            if (scene().materials[i].name == g.name) {
                used_[i] = true;
                return uint32_t(i);
            }
        for (const auto& c : converted_)
            if (c.path == path && c.index == index) return c.material;
        const RgbUpsampler& up = RgbUpsampler::srgb(reader_.library());
        Where mw = w.child(fmt::format("materials.{}", g.name));
        Material m = materialFromGltf(g, up, mw);
        // An image file of its own is read under the scene's path rules; an embedded one from memory.
        auto load = [&](const GltfImage& image, TextureRole role, TextureEncoding encoding) {
            if (image.isEmbedded())
                return loadTexture(EncodedImage{image.name, image.embedded}, role, encoding, 1.0, mw, reader_.textureGrid());
            reader_.readable().check(image.file, w, "texture file", image.name);
            return loadTexture(image.file, role, encoding, 1.0, mw, reader_.textureGrid());
        };
        if (g.baseColorTexture) {
            Texture tex = load(*g.baseColorTexture, TextureRole::Reflectance, TextureEncoding::Srgb);
            if (tex.kind == Texture::Kind::Rgb)  // glTF: base colour = factor × texel, in linear RGB
                for (size_t p = 0; p < tex.texels.size(); p += 3)
                    for (int c = 0; c < 3; ++c) tex.texels[p + c] *= float(g.baseColorFactor[c]);
            tex.where = mw;
            scene().textures.push_back(std::move(tex));
            m.textures.diffuse = int(scene().textures.size() - 1);
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
            scene().textures.push_back(std::move(tex));
            m.textures.normal = int(scene().textures.size() - 1);
        }
        scene().materials.push_back(std::move(m));
        used_.push_back(true);
        uint32_t added = uint32_t(scene().materials.size() - 1);
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
        for (const auto& m : scene().materials) names.push_back(m.name);
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
            fs::path path = reader_.readableFile(given, w.child("mesh"), "mesh file");
            // Without "material" the file's own materials are used (each overridable by a scene
            // material of the same name); with it, the whole mesh takes that material.
            const bool ownMaterials = !find(v, "material");
            GltfModel model;
            if (ownMaterials)
                model = loadGltf(path, w.child("mesh"), &reader_.readable());
            else
                out = loadGltfMesh(path, w.child("mesh"), &reader_.readable());
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
                    if (scene().materials[part.material].needsTextureCoordinates() && part.uvs.empty())
                        failInput(w.child("mesh"),
                                  "mesh file '{}': a primitive with material '{}' has textures but no TEXCOORD_0",
                                  given, scene().materials[part.material].name);
                    part.closed = isClosedOutward(part);
                    requireClosedMedium(part, w);
                    scene().meshes.push_back(std::move(part));
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
                int segments = sphereSegmentsFor(scene().camera, c, r);  // the camera is read first
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
        if (scene().materials[out.material].needsTextureCoordinates() && out.uvs.empty())
            failInput(w.child("material"),
                      "material '{}' has textures but this object has no texture coordinates (spheres have none; use "
                      "a quad or a glTF mesh with TEXCOORD_0)",
                      scene().materials[out.material].name);
        requireClosedMedium(out, w);
        scene().meshes.push_back(std::move(out));
    }

    // An absorbing medium fills a volume: the path length inside is measured between the faces a
    // ray enters and leaves by, which needs a closed mesh wound outwards (Mesh::closed).
    void requireClosedMedium(const Mesh& mesh, const Where& w) const {
        const Material& m = scene().materials[mesh.material];
        if (m.isMedium() && !mesh.closed)
            failInput(w.child("material"),
                      "material '{}' is an absorbing medium, which must fill a closed mesh wound outwards (a box, a "
                      "sphere, or a watertight glTF mesh); this object is open. For a sheet, give the material a "
                      "'transmittance' instead",
                      m.name);
    }

    // A csv: detector in the scene is a file like any other the scene names: relative to the
    // scene's folder, and subject to the same limits. Other names are checked by the display path.
    std::string detector(const std::string& name, const Where& w) {
        if (name.rfind("csv:", 0) != 0 || name.size() == 4) return name;
        std::string given = name.substr(4);
        fs::path path = reader_.readableFile(given, w, "detector file");
        return "csv:" + path.string();
    }

    Scene& scene() { return reader_.scene(); }
    const Scene& scene() const { return reader_.scene(); }

    SceneReader reader_;
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
