// What a scene may read: its own folder tree and the spectra library, judged on resolved paths
// by components; --allow-outside-paths lifts it. Temp folders with symlinks, and scenes that reach
// out through CSV spectra, meshes, glTF buffer URIs and csv: detectors.
#include "scene/readable_paths.h"

#include "scene/gltf_mesh.h"
#include "scene/scene_json.h"
#include "support/capture_warnings.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>

namespace fs = std::filesystem;
using namespace metamer;

namespace {

// A fresh folder per test: <tmp>/metamer-readable-<pid>/<name>, with the real path (the temp
// folder itself may be a symlink, e.g. on macOS).
fs::path freshRoot(const std::string& name) {
    fs::path d = fs::temp_directory_path() / ("metamer-readable-" + std::to_string(::getpid())) / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return fs::canonical(d);
}

void writeFile(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
}

const std::string kCsv = "wavelength_nm,value\n380,0.5\n780,0.5\n";

// A scene whose one material's diffuse spectrum is `diffuse` (JSON), plus `extra` top-level JSON.
std::string scene(const std::string& diffuse, const std::string& objects = "", const std::string& extra = "") {
    std::string objs = objects.empty()
                           ? R"([{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "segments": 8, "material": "m"}])"
                           : objects;
    return R"({"grid": {"start_nm": 400, "end_nm": 700, "step_nm": 10},
               "camera": {"position": [0, 0, 3], "target": [0, 0, 0], "width": 8, "height": 8},
               "lights": [{"type": "ambient", "spectrum": 1}],
               "materials": {"m": {"diffuse": )" +
           diffuse + R"(}}, "objects": )" + objs + extra + "}";
}

// A glTF triangle whose buffer is the external file `uri` (36 bytes of positions, 6 of indices).
std::string gltfWithBuffer(const std::string& uri) {
    return R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
              "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
              "buffers": [{"uri": ")" +
           uri + R"(", "byteLength": 44}],
              "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                              {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
              "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                             "min": [0, 0, 0], "max": [1, 1, 0]},
                            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})";
}

std::string triangleBuffer() {
    float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint16_t i[4] = {0, 1, 2, 0};
    std::string b(reinterpret_cast<const char*>(p), sizeof p);
    b.append(reinterpret_cast<const char*>(i), sizeof i);
    return b;
}

std::string loadError(const fs::path& sceneFile, const SpectrumLibrary& lib, bool allow = false) {
    try {
        LoadOptions o;
        o.allowOutsidePaths = allow;
        loadScene(sceneFile, lib, {}, o);
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        return e.what();
    }
    return "";
}

const SpectrumLibrary& library() {
    static SpectrumLibrary lib(fs::path(METAMER_TEST_DATA_DIR) / "scene" / "spectra");
    return lib;
}

}  // namespace

TEST(ReadablePaths, ContainmentIsByComponentsNotStringPrefix) {
    fs::path root = freshRoot("components");
    fs::create_directories(root / "scenes" / "sub");
    fs::create_directories(root / "scenes2");
    EXPECT_TRUE(isInsideFolder(root / "scenes" / "sub" / "x.csv", root / "scenes"));
    EXPECT_TRUE(isInsideFolder(root / "scenes", root / "scenes"));
    EXPECT_TRUE(isInsideFolder(root / "scenes" / "new" / "x.csv", root / "scenes"));  // need not exist
    EXPECT_FALSE(isInsideFolder(root / "scenes2" / "x.csv", root / "scenes"));
    EXPECT_FALSE(isInsideFolder(root / "scenes" / ".." / "scenes2" / "x.csv", root / "scenes"));
    EXPECT_FALSE(isInsideFolder(root / "x.csv", root / "scenes"));
    EXPECT_TRUE(isInsideFolder(root / "scenes" / "sub" / ".." / "x.csv", root / "scenes" / ""));
}

TEST(ReadablePaths, SymlinksAreFollowed) {
    fs::path root = freshRoot("symlinks");
    fs::create_directories(root / "scenes");
    fs::create_directories(root / "elsewhere");
    writeFile(root / "elsewhere" / "secret.csv", kCsv);
    fs::create_symlink(root / "elsewhere", root / "scenes" / "link");
    fs::create_symlink(root / "elsewhere" / "secret.csv", root / "scenes" / "file.csv");
    EXPECT_FALSE(isInsideFolder(root / "scenes" / "link" / "secret.csv", root / "scenes"));
    EXPECT_FALSE(isInsideFolder(root / "scenes" / "file.csv", root / "scenes"));
    // A link to a folder inside is inside; a scene folder reached through a link is its target.
    fs::create_directories(root / "scenes" / "data");
    fs::create_symlink(root / "scenes" / "data", root / "scenes" / "data-link");
    EXPECT_TRUE(isInsideFolder(root / "scenes" / "data-link" / "x.csv", root / "scenes"));
    fs::create_symlink(root / "scenes", root / "scenes-link");
    EXPECT_TRUE(isInsideFolder(root / "scenes" / "data" / "x.csv", root / "scenes-link"));
}

TEST(ReadablePaths, PolicyForASceneAllowsItsFolderAndTheLibrary) {
    fs::path root = freshRoot("policy");
    fs::path lib = root / "lib";
    fs::create_directories(lib);
    ReadablePaths p = ReadablePaths::forScene(root / "scenes" / "a.json", lib, false);
    EXPECT_TRUE(p.restricted());
    EXPECT_TRUE(p.allows(root / "scenes" / "x.csv"));
    EXPECT_TRUE(p.allows(lib / "illuminants" / "D65.csv"));
    EXPECT_FALSE(p.allows(root / "other" / "x.csv"));
    EXPECT_FALSE(p.allows("/etc/passwd"));
    ReadablePaths open = ReadablePaths::forScene(root / "scenes" / "a.json", lib, true);
    EXPECT_FALSE(open.restricted());
    EXPECT_TRUE(open.allows("/etc/passwd"));
    EXPECT_TRUE(ReadablePaths::anywhere().allows("/etc/passwd"));
    try {
        p.check(root / "other" / "x.csv", Where{"a.json", "materials.m.diffuse"}, "spectrum file", "../other/x.csv");
        FAIL() << "no error";
    } catch (const Error& e) {
        std::string m = e.what();
        EXPECT_NE(m.find("a.json: materials.m.diffuse: spectrum file '../other/x.csv'"), std::string::npos) << m;
        EXPECT_NE(m.find("--allow-outside-paths"), std::string::npos) << m;
    }
}

TEST(ReadablePaths, SceneCsvSpectraOutsideAreRefusedUnlessAllowed) {
    fs::path root = freshRoot("csv");
    writeFile(root / "outside.csv", kCsv);
    writeFile(root / "scenes2" / "near.csv", kCsv);
    writeFile(root / "scenes" / "inside" / "ok.csv", kCsv);
    writeFile(root / "scenes" / "ok.json", scene(R"("inside/ok.csv")"));
    EXPECT_EQ(loadError(root / "scenes" / "ok.json", library()), "");

    writeFile(root / "scenes" / "up.json", scene(R"("../outside.csv")"));
    std::string e = loadError(root / "scenes" / "up.json", library());
    EXPECT_NE(e.find("up.json: materials.m.diffuse: spectrum file '../outside.csv'"), std::string::npos) << e;
    EXPECT_NE(e.find("--allow-outside-paths"), std::string::npos) << e;
    EXPECT_EQ(loadError(root / "scenes" / "up.json", library(), true), "");

    // A sibling folder whose name starts with the scene folder's is still outside.
    writeFile(root / "scenes" / "sibling.json", scene(R"("../scenes2/near.csv")"));
    EXPECT_NE(loadError(root / "scenes" / "sibling.json", library()).find("outside"), std::string::npos);

    // An absolute path, and a symlink inside the folder pointing out.
    writeFile(root / "scenes" / "absolute.json", scene("\"" + (root / "outside.csv").string() + "\""));
    EXPECT_NE(loadError(root / "scenes" / "absolute.json", library()).find("outside"), std::string::npos);
    fs::create_symlink(root / "outside.csv", root / "scenes" / "link.csv");
    writeFile(root / "scenes" / "link.json", scene(R"("link.csv")"));
    e = loadError(root / "scenes" / "link.json", library());
    EXPECT_NE(e.find("spectrum file 'link.csv' (" + (root / "outside.csv").string() + ")"), std::string::npos) << e;
    EXPECT_EQ(loadError(root / "scenes" / "link.json", library(), true), "");

    // The library is readable from anywhere: its own files by name.
    writeFile(root / "scenes" / "lib.json", scene(R"("colorchecker/dark_skin")"));
    EXPECT_EQ(loadError(root / "scenes" / "lib.json", library()), "");
}

TEST(ReadablePaths, MeshesAndTheirBuffersOutsideAreRefused) {
    fs::path root = freshRoot("mesh");
    writeFile(root / "outside" / "tri.bin", triangleBuffer());
    writeFile(root / "outside" / "tri.gltf", gltfWithBuffer("tri.bin"));
    writeFile(root / "scenes" / "assets" / "tri.bin", triangleBuffer());
    writeFile(root / "scenes" / "assets" / "ok.gltf", gltfWithBuffer("tri.bin"));
    writeFile(root / "scenes" / "assets" / "up.gltf", gltfWithBuffer("../../outside/tri.bin"));
    writeFile(root / "scenes" / "assets" / "abs.gltf", gltfWithBuffer((root / "outside" / "tri.bin").string()));
    auto meshScene = [](const std::string& mesh) {
        return scene("0.5", R"([{"mesh": ")" + mesh + R"(", "material": "m"}])");
    };
    writeFile(root / "scenes" / "ok.json", meshScene("assets/ok.gltf"));
    EXPECT_EQ(loadError(root / "scenes" / "ok.json", library()), "");

    writeFile(root / "scenes" / "mesh-up.json", meshScene("../outside/tri.gltf"));
    std::string e = loadError(root / "scenes" / "mesh-up.json", library());
    EXPECT_NE(e.find("objects.0.mesh: mesh file '../outside/tri.gltf'"), std::string::npos) << e;
    EXPECT_EQ(loadError(root / "scenes" / "mesh-up.json", library(), true), "");

    // A glTF inside whose buffer URI climbs out, or is absolute.
    writeFile(root / "scenes" / "buffer-up.json", meshScene("assets/up.gltf"));
    e = loadError(root / "scenes" / "buffer-up.json", library());
    EXPECT_NE(e.find("objects.0.mesh: mesh file"), std::string::npos) << e;
    EXPECT_NE(e.find("referenced file"), std::string::npos) << e;
    EXPECT_NE(e.find((root / "outside" / "tri.bin").string()), std::string::npos) << e;
    EXPECT_EQ(loadError(root / "scenes" / "buffer-up.json", library(), true), "");
    // tinygltf joins even an absolute URI to the glTF's folder (then to the current directory), so
    // it does not reach the file outside; either way it must not load.
    writeFile(root / "scenes" / "buffer-abs.json", meshScene("assets/abs.gltf"));
    EXPECT_NE(loadError(root / "scenes" / "buffer-abs.json", library()), "");

    // tinygltf's fallback to the current directory is outside too.
    writeFile(root / "cwd" / "cwd-only.bin", triangleBuffer());
    writeFile(root / "scenes" / "assets" / "cwd.gltf", gltfWithBuffer("cwd-only.bin"));
    writeFile(root / "scenes" / "buffer-cwd.json", meshScene("assets/cwd.gltf"));
    fs::path cwd = fs::current_path();
    fs::current_path(root / "cwd");
    e = loadError(root / "scenes" / "buffer-cwd.json", library());
    fs::current_path(cwd);
    EXPECT_NE(e.find("referenced file"), std::string::npos) << e;

    // A buffer that is a symlink out of the folder.
    fs::create_symlink(root / "outside" / "tri.bin", root / "scenes" / "assets" / "linked.bin");
    writeFile(root / "scenes" / "assets" / "linked.gltf", gltfWithBuffer("linked.bin"));
    writeFile(root / "scenes" / "buffer-link.json", meshScene("assets/linked.gltf"));
    EXPECT_NE(loadError(root / "scenes" / "buffer-link.json", library()).find("referenced file"), std::string::npos);

    // loadGltfMesh without a policy (trusted callers) reads anything.
    EXPECT_NO_THROW(loadGltfMesh(root / "scenes" / "assets" / "up.gltf", Where{"t", "mesh"}));
}

TEST(ReadablePaths, ImagesOutsideAreNotReadButOnlyWarnedAbout) {
    // Images are read by tinygltf but never used: one outside is skipped with a warning.
    fs::path root = freshRoot("image");
    writeFile(root / "outside" / "tex.png", "not really a png");
    writeFile(root / "scenes" / "assets" / "tri.bin", triangleBuffer());
    std::string gltf = gltfWithBuffer("tri.bin");
    gltf.insert(gltf.size() - 1, R"(, "images": [{"uri": "../../outside/tex.png"}])");
    writeFile(root / "scenes" / "assets" / "textured.gltf", gltf);
    writeFile(root / "scenes" / "textured.json",
              scene("0.5", R"([{"mesh": "assets/textured.gltf", "material": "m"}])"));
    std::string e;
    {
        test::CaptureWarnings warnings;
        e = loadError(root / "scenes" / "textured.json", library());
    }
    EXPECT_EQ(e, "");
    EXPECT_TRUE(test::CaptureWarnings::any("not read")) << ::testing::PrintToString(test::CaptureWarnings::lines());
}

TEST(ReadablePaths, CsvDetectorInTheOutputBlockIsRelativeToTheSceneAndChecked) {
    fs::path root = freshRoot("detector");
    writeFile(root / "outside" / "det.csv", "wavelength_nm,a\n400,1\n700,1\n");
    writeFile(root / "scenes" / "det.csv", "wavelength_nm,a\n400,1\n700,1\n");
    writeFile(root / "scenes" / "in.json", scene("0.5", "", R"(, "output": {"detector": "csv:det.csv"})"));
    LoadOptions o;
    Scene s = loadScene(root / "scenes" / "in.json", library(), {}, o);
    ASSERT_TRUE(s.output.detector);
    EXPECT_EQ(*s.output.detector, "csv:" + (root / "scenes" / "det.csv").string());

    writeFile(root / "scenes" / "out.json",
              scene("0.5", "", R"(, "output": {"detector": "csv:../outside/det.csv"})"));
    std::string e = loadError(root / "scenes" / "out.json", library());
    EXPECT_NE(e.find("out.json: output.detector: detector file '../outside/det.csv'"), std::string::npos) << e;
    EXPECT_EQ(loadError(root / "scenes" / "out.json", library(), true), "");
    // Library detectors are names, not files.
    writeFile(root / "scenes" / "named.json", scene("0.5", "", R"(, "output": {"detector": "cie1964"})"));
    EXPECT_EQ(loadError(root / "scenes" / "named.json", library()), "");
}
