// What the scene-file tests share (scene_json_test, material_reader_{opaque,transparent,paint}_test,
// overrides_test, bundled_scenes_test): a valid scene exercising every feature, loading one from
// a string as if it were tests/data/scene/test.json, the input error a load throws, and the bad-input
// case table's row and fixture (SceneJsonBad; its test is in scene_json_test.cpp, and each file
// instantiates it with the cases of the code it tests).
#pragma once

#include "core/error.h"
#include "scene/scene_json.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace metamer::test {

using Json = nlohmann::ordered_json;

inline const std::filesystem::path kData = std::filesystem::path(METAMER_TEST_DATA_DIR) / "scene";

inline const SpectrumLibrary& fixtureLibrary() {
    static SpectrumLibrary lib(kData / "spectra");
    return lib;
}

// A valid scene exercising every feature; each bad-input case (BadCase) breaks one thing.
inline Json baseScene() {
    return Json::parse(R"({
      "description": "test scene",
      "grid": {"start_nm": 380, "end_nm": 780, "step_nm": 10},
      "camera": {"projection": "perspective", "position": [0, 1, 6], "target": [0, 0, 0],
                 "up": [0, 1, 0], "fov_y_deg": 35, "width": 64, "height": 48},
      "lights": [
        {"type": "ambient", "spectrum": "illuminants/D65", "scale": 0.02},
        {"type": "directional", "direction": [0, -2, 0], "spectrum": "illuminants/D65", "scale": 1.0},
        {"type": "point", "position": [2, 3, 2], "spectrum": "illuminants/A", "scale": 20.0}
      ],
      "materials": {
        "skin": {"diffuse": "colorchecker/dark_skin", "specular": 0.04, "gloss": 40},
        "white": {"diffuse": 0.8},
        "local": {"diffuse": "local.csv"},
        "inline": {"diffuse": {"wavelengths_nm": [400, 700], "values": [0.1, 0.7]}},
        "gold": {"diffuse": 0, "specular": "metals/gold", "gloss": 200},
        "brightener": {"diffuse": 0.8, "fluorescence": {"excitation": "fluorescent/brightener_ex",
                       "emission": "fluorescent/brightener_em", "quantum_yield": 0.9}}
      },
      "objects": [
        {"shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "skin", "segments": 16},
        {"shape": "quad", "center": [0, -1, 0], "normal": [0, 2, 0], "size": [8, 4], "material": "brightener"},
        {"mesh": "cube.gltf", "translate": [2, 0, 0], "rotate_deg": [0, 30, 0], "scale": 0.5, "material": "gold"},
        {"shape": "sphere", "center": [3, 0, 0], "radius": 0.5, "material": "white"},
        {"shape": "quad", "center": [0, 0, -2], "normal": [0, 0, 1], "size": [1, 1], "material": "local"},
        {"shape": "quad", "center": [0, 0, -3], "normal": [0, 0, 1], "size": [1, 1], "up": [1, 1, 0], "material": "inline"}
      ]
    })");
}

// In-memory scenes are "placed" in the fixture folder so relative paths resolve there.
inline Scene load(const Json& doc, const std::vector<std::string>& overrides = {}) {
    return loadSceneFromString(doc.dump(2), kData / "test.json", fixtureLibrary(), overrides);
}

inline std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput) << e.what();
        return e.what();
    }
    return "(no error)";
}

inline Json parse(const char* s) { return Json::parse(s); }

// One bad input: an edit that breaks baseScene() in one place, and what the error must say.
struct BadCase {
    const char* name;
    std::function<void(Json&)> edit;
    const char* key;      // must appear in what()
    const char* message;  // must appear in what()
};

// Print a case by its name (CTest shows the parameter; a byte dump of the struct helps nobody).
inline void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }

class SceneJsonBad : public ::testing::TestWithParam<BadCase> {};

// The case's name is the test's name (All/SceneJsonBad.NamesFileKeyAndProblem/<name>).
inline std::string badCaseName(const ::testing::TestParamInfo<BadCase>& info) { return info.param.name; }

}  // namespace metamer::test
