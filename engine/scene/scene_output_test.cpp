// The scene's "output" block (docs/scene-format.md, "Output").
#include "scene/scene_json.h"

#include <gtest/gtest.h>

#include <filesystem>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

const SpectrumLibrary& library() {
    static SpectrumLibrary lib(fs::path(METAMER_TEST_DATA_DIR) / "scene" / "spectra");
    return lib;
}

std::string scene(const std::string& output) {
    return R"({"camera": {"position": [0, 0, 5], "target": [0, 0, 0], "width": 8, "height": 8},
               "lights": [{"type": "ambient", "spectrum": 1.0}],
               "materials": {"m": {"diffuse": 0.5}},
               "objects": [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [1, 1], "material": "m"}],
               "output": )" + output + "}";
}

std::string errorOf(const std::string& output) {
    try {
        loadSceneFromString(scene(output), "dir/s.json", library());
    } catch (const Error& e) {
        return e.what();
    }
    return "no error";
}

}  // namespace

TEST(SceneOutput, EveryKeyIsRead) {
    Scene s = loadSceneFromString(scene(R"({"detector": "camera:nikon_d5100", "adaptation": "cat16",
        "display": "crt", "bits": 16, "integration": "trapezoid", "xyz": "absolute", "write": ["cube", "xyz"]})"),
                                  "dir/s.json", library());
    EXPECT_EQ(*s.output.detector, "camera:nikon_d5100");
    EXPECT_EQ(*s.output.adaptation, "cat16");
    EXPECT_EQ(*s.output.display, "crt");
    EXPECT_EQ(*s.output.bits, 16);
    EXPECT_EQ(*s.output.integration, "trapezoid");
    EXPECT_EQ(*s.output.xyz, "absolute");
    EXPECT_EQ(s.output.write->size(), 2u);
    EXPECT_EQ(s.output.where.key, "output");
}

TEST(SceneOutput, AbsentBlockLeavesEverythingUnset) {
    Scene s = loadSceneFromString(scene("{}"), "dir/s.json", library());
    EXPECT_FALSE(s.output.detector || s.output.bits || s.output.write);
}

TEST(SceneOutput, BadValuesNameFileAndKey) {
    EXPECT_NE(errorOf(R"({"bits": 12})").find("dir/s.json: output.bits: must be 8 or 16"), std::string::npos)
        << errorOf(R"({"bits": 12})");
    EXPECT_NE(errorOf(R"({"write": ["cube", "pgn"]})").find("output.write.1: 'pgn' is not one of"), std::string::npos);
    EXPECT_NE(errorOf(R"({"write": ["cube", "pgn"]})").find("did you mean 'png'"), std::string::npos);
    EXPECT_NE(errorOf(R"({"detecter": "cie1931"})").find("output.detecter: unknown key"), std::string::npos);
    EXPECT_NE(errorOf(R"({"integration": "simpson"})").find("output.integration"), std::string::npos);
    EXPECT_NE(errorOf(R"({"xyz": 1})").find("output.xyz: expected a string"), std::string::npos);
    EXPECT_NE(errorOf(R"("srgb")").find("output: expected an object"), std::string::npos) << errorOf(R"("srgb")");
}
