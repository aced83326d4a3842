// The bundled scenes (scenes/*.json) load with the real spectra library, their grids covering them.
#include "scene/scene_json.h"

#include "scene/scene_on_grid.h"
#include "support/capture_warnings.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

using namespace metamer;
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

using test::CaptureWarnings;

namespace {

// Library names a scene refers to (strings in spectrum positions that are not .csv paths).
void libraryNames(const Json& v, std::vector<std::string>& out) {
    static const std::set<std::string> keys = {"spectrum", "diffuse", "specular", "excitation", "emission"};
    if (v.is_object()) {
        for (auto it = v.begin(); it != v.end(); ++it) {
            if (it.key() == "textures") continue;  // file names, not spectra
            if (keys.count(it.key()) && it.value().is_string()) {
                std::string s = it.value().get<std::string>();
                if (s.size() < 4 || s.substr(s.size() - 4) != ".csv") out.push_back(s);
            }
            libraryNames(it.value(), out);
        }
    } else if (v.is_array()) {
        for (const auto& e : v) libraryNames(e, out);
    }
}

void expectWellFormedMeshes(const Scene& s) {
    for (const Mesh& m : s.meshes) {
        ASSERT_EQ(m.normals.size(), m.positions.size()) << m.name;
        ASSERT_EQ(m.indices.size() % 3, 0u) << m.name;
        for (const auto& n : m.normals) ASSERT_NEAR(glm::length(n), 1.0, 1e-9) << m.name;
        size_t disagree = 0;
        for (size_t t = 0; t < m.indices.size(); t += 3) {
            const auto* i = &m.indices[t];
            glm::dvec3 g = glm::cross(m.positions[i[1]] - m.positions[i[0]], m.positions[i[2]] - m.positions[i[0]]);
            if (glm::dot(g, m.normals[i[0]] + m.normals[i[1]] + m.normals[i[2]]) <= 0) ++disagree;
        }
        EXPECT_EQ(disagree, 0u) << m.name << ": triangles wound against their normals";
    }
}

}  // namespace

TEST(BundledScenes, LoadWithTheRealLibrary) {
    fs::path root = METAMER_SOURCE_DIR;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(root / "scenes"))
        if (e.path().extension() == ".json") files.push_back(e.path());
    files.push_back(root / "scenes" / "dataset" / "scene.json");  // the training-set sweep's base scene
    std::sort(files.begin(), files.end());
    ASSERT_GE(files.size(), 4u);
    ASSERT_TRUE(fs::is_directory(root / "spectra")) << root;
    SpectrumLibrary lib(root / "spectra");
    for (const auto& file : files) {
        SCOPED_TRACE(file.string());
        std::ifstream in(file);
        Json doc = Json::parse(in);
        std::vector<std::string> names;
        libraryNames(doc, names);
        for (const auto& n : names)
            ASSERT_TRUE(lib.contains(n)) << "the library has no " << n;
        CaptureWarnings warnings;
        Scene s = loadScene(file, lib);
        EXPECT_TRUE(!s.lights.empty() || s.hasEmitters());  // something lights it
        EXPECT_FALSE(s.meshes.empty());
        expectWellFormedMeshes(s);
        // The bundled grids cover every spectrum they use: no coverage warnings.
        SceneOnGrid g = resampleScene(s, s.grid, CoveragePolicy::Error);
        EXPECT_EQ(g.lights.size(), s.lights.size());
        EXPECT_TRUE(warnings.lines().empty()) << warnings.lines().front();
    }
}

TEST(BundledScenes, ColorCheckerHasTheTwentyFourPatches) {
    fs::path root = METAMER_SOURCE_DIR;
    SpectrumLibrary lib(root / "spectra");
    ASSERT_TRUE(lib.contains("colorchecker/black_2") && lib.contains("illuminants/D65"));
    Scene s = loadScene(root / "scenes" / "colorchecker.json", lib);
    EXPECT_EQ(s.camera.projection, Camera::Projection::Orthographic);
    EXPECT_EQ(s.camera.width, 600);
    EXPECT_EQ(s.camera.height, 400);
    int patches = 0;
    for (const auto& m : s.materials) patches += m.diffuse.spectrum.source.rfind("colorchecker/", 0) == 0;
    EXPECT_EQ(patches, 24);
    EXPECT_EQ(s.meshes.size(), 25u);
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].direction, glm::dvec3(0, 0, -1));  // along the view axis
}

TEST(BundledScenes, FluorescentLightCanBeSwitched) {
    fs::path root = METAMER_SOURCE_DIR;
    SpectrumLibrary lib(root / "spectra");
    for (const char* name : {"illuminants/A", "illuminants/D65", "illuminants/blacklight", "fluorescent/pink_dye_em"})
        ASSERT_TRUE(lib.contains(name)) << "the library has no " << name;
    for (const char* name : {"illuminants/A", "illuminants/D65", "illuminants/blacklight"}) {
        CaptureWarnings warnings;
        Scene s = loadScene(root / "scenes" / "fluorescent.json", lib, {std::string("lights.0.spectrum=") + name});
        ASSERT_EQ(s.lights.size(), 1u);
        EXPECT_EQ(s.lights[0].spectrum.spectrum.source, name);
        EXPECT_TRUE(s.hasFluorescence());
        resampleScene(s, s.grid);
        // Only a light whose data stop short of the grid may warn, and only about itself.
        for (const auto& w : warnings.lines()) EXPECT_NE(w.find("lights.0.spectrum"), std::string::npos) << w;
    }
}

TEST(BundledScenes, SpheresAreTessellatedForTheCameraAndClosedMeshesAreKnown) {
    // spheres.json says no segments: its 0.5 m spheres, about 6.6 m from a 40° camera on 512 rows,
    // are 53 px in radius, so 56 segments (3 024 triangles); a --set of the size changes them. The
    // torus of mesh.json (glTF, its seam duplicated for UVs) is closed; quads are not.
    fs::path root = METAMER_SOURCE_DIR;
    SpectrumLibrary lib(root / "spectra");
    Scene s = loadScene(root / "scenes" / "spheres.json", lib);
    ASSERT_EQ(s.meshes.size(), 5u);
    EXPECT_FALSE(s.meshes[0].closed);
    for (size_t i = 1; i < 5; ++i) {
        EXPECT_EQ(s.meshes[i].indices.size() / 3, 3024u) << i;
        EXPECT_TRUE(s.meshes[i].closed);
    }
    Scene small = loadScene(root / "scenes" / "spheres.json", lib, {"camera.width=64", "camera.height=64"});
    EXPECT_EQ(small.meshes[1].indices.size() / 3, size_t(2 * 16 * 7));  // 16 segments
    Scene mesh = loadScene(root / "scenes" / "mesh.json", lib);
    bool torus = false;
    for (const Mesh& m : mesh.meshes)
        if (m.name.find("torus") != std::string::npos) torus = m.closed;
    EXPECT_TRUE(torus);
}
