// What every reader of a scene file shares (internal to scene/): the spectra library, the scene
// file and the paths it may read, the grid textures are checked against, the Scene as read so far
// (earlier materials, textures), and the value forms a scene gives in many places: spectra,
// Donaldson matrices, refractive indices and texture references. scene/scene_json.cpp reads the
// document's structure with it; the material models' readers (scene/material_readers.h) read
// their keys with it. Every error names the file and the key path.
// Tests: engine/scene/scene_json_test.cpp, engine/scene/scene_donaldson_test.cpp,
// tests/bad_inputs_test.cpp (tests/bad-inputs/), tests/textures_test.cpp.
#pragma once

#include "scene/json_values.h"
#include "scene/readable_paths.h"
#include "scene/scene.h"
#include "scene/texture.h"
#include "spectral/dielectric.h"
#include "spectral/library.h"

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

class SceneReader {
public:
    // Paths resolve against `file`'s folder and are limited to it and the library unless
    // `allowOutsidePaths`; `renderGrid` is the job's grid when it is not the scene's (LoadOptions).
    SceneReader(const SpectrumLibrary& lib, const std::filesystem::path& file, bool allowOutsidePaths,
                std::optional<Grid> renderGrid);

    // The scene as read so far: a paint's substrate names an earlier material, and the textures
    // read are shared by the materials that name the same file the same way.
    Scene& scene() { return scene_; }
    const Scene& scene() const { return scene_; }
    const SpectrumLibrary& library() const { return lib_; }
    const std::filesystem::path& file() const { return file_; }
    const ReadablePaths& readable() const { return readable_; }

    // The file `given` names, relative to the scene's folder; an input error at `w` when the scene
    // may not read it (`what` says what the file is: "spectrum file", "mesh file").
    std::filesystem::path readableFile(const std::string& given, const Where& w, const std::string& what) const;

    // A spectrum: a library name, a .csv path, a number or {"wavelengths_nm": [...], "values":
    // [...]}; checked for `kind` (a constant out of range is an error, sampled data a warning).
    SceneSpectrum spectrum(const json_read::Json& v, const Where& w, SpectrumKind kind);
    // A Donaldson matrix: a .csv or .exr file relative to the scene, or a library name.
    SceneMatrix matrix(const json_read::Json& v, const Where& w);
    // A non-empty array of numbers.
    std::vector<double> numbers(const json_read::Json& v, const Where& w);
    // A refractive index n(λ) (a slab's and a paint surface's "ior") and how the scene gave it.
    std::pair<RefractiveIndex, std::string> refractiveIndex(const json_read::Json& n, const Where& iw);
    // A texture file name or {"file": ...}, read once per path, role, encoding and scale; its
    // index in scene().textures.
    int textureRef(const json_read::Json& v, const Where& w, TextureRole role);

    // The grid textures will be resampled to: the job's when it sets one, else the scene's (read
    // before the materials), so an oversized texture is refused before it is decoded.
    const Grid* textureGrid() const { return renderGrid_ ? &*renderGrid_ : &scene_.grid; }

private:
    struct TextureKey {
        std::filesystem::path path;
        TextureRole role;
        TextureEncoding encoding;
        double scale;
    };

    const SpectrumLibrary& lib_;
    std::filesystem::path file_;
    std::filesystem::path dir_;
    ReadablePaths readable_;
    std::optional<Grid> renderGrid_;
    Scene scene_;
    std::vector<TextureKey> textureKeys_;
};

}  // namespace metamer
