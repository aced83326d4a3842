// Scene files: JSON in, a validated Scene out (format: docs/scene-format.md). Every error is an
// input error naming the file and the key path (or the line, for JSON syntax).
// Tests: in engine/scene/, scene_json_test.cpp (the document), material_reader_opaque_test.cpp,
// material_reader_transparent_test.cpp and material_reader_paint_test.cpp (the material models),
// overrides_test.cpp (--set), bundled_scenes_test.cpp, scene_output_test.cpp and
// scene_donaldson_test.cpp; tests/bad_inputs_test.cpp.
#pragma once

#include "scene/scene.h"
#include "spectral/library.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace metamer {

struct LoadOptions {
    // A scene may read files (CSV spectra, glTF meshes and their buffers and images, csv:
    // detectors) only inside its own folder tree and the spectra library, unless this is set
    // (--allow-outside-paths; docs/scene-format.md, "Paths and what a scene may read").
    bool allowOutsidePaths = false;
    // The grid the scene will be rendered on when it is not the scene's own (--grid): textures are
    // checked against it, from their headers, before they are decoded (scene/texture.h).
    std::optional<Grid> grid;
};

// Reads `file`, applies `overrides` ("KEY=VALUE", as given to --set) and interprets the result.
// Library names resolve through `lib`; CSV and mesh paths resolve against the file's folder.
Scene loadScene(const std::filesystem::path& file, const SpectrumLibrary& lib,
                const std::vector<std::string>& overrides = {}, const LoadOptions& options = {});

// The same from text already in memory; `file` is used for messages and to resolve paths.
Scene loadSceneFromString(const std::string& text, const std::filesystem::path& file,
                          const SpectrumLibrary& lib, const std::vector<std::string>& overrides = {},
                          const LoadOptions& options = {});

}  // namespace metamer
