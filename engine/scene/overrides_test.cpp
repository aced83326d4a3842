// `--set KEY=VALUE` overrides (scene/overrides.cpp), checked like the file's own values.
#include "scene/scene_json_test_util.h"

#include <gtest/gtest.h>

using namespace metamer;
using namespace metamer::test;

TEST(SceneOverrides, ChangeValues) {
    Scene s = load(baseScene(), {"lights.1.spectrum=illuminants/A", "camera.width=256", "lights.0.scale=0.5",
                                 "camera.position=[0, 2, 6]", "objects.3.segments=8",
                                 R"(grid={"start_nm": 400, "end_nm": 700, "step_nm": 5})"});
    EXPECT_EQ(s.lights[1].spectrum.spectrum.source, "illuminants/A");
    EXPECT_EQ(s.camera.width, 256);
    EXPECT_DOUBLE_EQ(s.lights[0].scale, 0.5);
    EXPECT_EQ(s.camera.position, glm::dvec3(0, 2, 6));
    EXPECT_EQ(s.meshes[3].indices.size() / 3, size_t(2 * 8 * 3));  // a new key in an existing object
    EXPECT_EQ(s.grid, (Grid{400, 700, 5}));
}

TEST(SceneOverrides, QuotedJsonStringAndLaterWins) {
    Scene s = load(baseScene(), {R"(lights.1.spectrum="illuminants/A")", "camera.width=10", "camera.width=20"});
    EXPECT_EQ(s.lights[1].spectrum.spectrum.source, "illuminants/A");
    EXPECT_EQ(s.camera.width, 20);
}

TEST(SceneOverrides, BadPathsNameTheOverride) {
    struct Case {
        const char* text;
        const char* expected;
    } cases[] = {
        {"lights.5.scale=0.5", "test.json: lights.5: --set lights.5.scale=0.5: no element 5; 'lights' has 3"},
        {"lights.x.scale=0.5", "test.json: lights.x: --set lights.x.scale=0.5: 'lights' is an array"},
        {"camer.width=1", "test.json: camer: --set camer.width=1: no such key; did you mean 'camera'?"},
        {"camera.nope.x=1", "test.json: camera.nope: --set camera.nope.x=1: no such key"},
        {"camera.width.x=1", "test.json: camera.width: --set camera.width.x=1: 'camera.width' is a number"},
        {"camera.width", "test.json: --set camera.width: expected KEY=VALUE"},
        {"camera..width=1", "test.json: --set camera..width=1: 'camera..width' is not a key path"},
        {"=1", "test.json: --set =1: '' is not a key path"},
    };
    for (const auto& c : cases) {
        std::string what = errorOf([&] { load(baseScene(), {c.text}); });
        EXPECT_NE(what.find(c.expected), std::string::npos) << c.text << "\n" << what;
    }
}

TEST(SceneOverrides, BadValuesAreCheckedLikeTheFileAndNameTheOverride) {
    std::string what = errorOf([&] { load(baseScene(), {"camera.width=abc"}); });
    EXPECT_NE(what.find("test.json: camera.width: expected an integer, got a string (from --set camera.width=abc)"),
              std::string::npos)
        << what;
    what = errorOf([&] { load(baseScene(), {"camera.fov=20"}); });
    EXPECT_NE(what.find("camera.fov: unknown key for a perspective camera; did you mean 'fov_y_deg'? (from --set "
                        "camera.fov=20)"),
              std::string::npos)
        << what;
    what = errorOf([&] { load(baseScene(), {"lights.0.spectrum=illuminants/B"}); });
    EXPECT_NE(what.find("lights.0.spectrum: no spectrum 'illuminants/B'"), std::string::npos) << what;
    EXPECT_NE(what.find("(from --set lights.0.spectrum=illuminants/B)"), std::string::npos) << what;
}
