#include "scene/gltf_mesh.h"

#include "core/memory_limits.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <unistd.h>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

const fs::path kData = fs::path(METAMER_TEST_DATA_DIR) / "scene";
const Where kWhere{"scene.json", "objects.7.mesh"};

glm::dvec3 faceNormal(const Mesh& m, size_t t) {
    const auto* i = &m.indices[3 * t];
    return glm::normalize(glm::cross(m.positions[i[1]] - m.positions[i[0]], m.positions[i[2]] - m.positions[i[0]]));
}

// Faces are flat (per-face normals in the file, or computed over unshared vertices), so each
// triangle's right-hand normal must equal each of its vertex normals.
void expectFlatFacesAgree(const Mesh& m) {
    for (size_t t = 0; t < m.indices.size() / 3; ++t)
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3& n = m.normals[m.indices[3 * t + k]];
            EXPECT_NEAR(glm::length(n), 1.0, 1e-9);
            EXPECT_NEAR(glm::distance(n, faceNormal(m, t)), 0.0, 1e-6) << "triangle " << t;
        }
}

void checkCube(const Mesh& m) {
    // Unit cube; node chain: translate (1, 2, 3) · rotate 90° about y · scale 2.
    ASSERT_EQ(m.positions.size(), 24u);
    ASSERT_EQ(m.indices.size(), 36u);
    glm::dvec3 lo(1e9), hi(-1e9);
    for (const auto& p : m.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    EXPECT_NEAR(glm::distance(lo, glm::dvec3(0, 1, 2)), 0.0, 1e-6);
    EXPECT_NEAR(glm::distance(hi, glm::dvec3(2, 3, 4)), 0.0, 1e-6);
    expectFlatFacesAgree(m);
    // The file's +x face now faces -z (x -> -z under the rotation) and sits at z = 2.
    int found = 0;
    for (size_t i = 0; i < m.positions.size(); ++i)
        if (glm::distance(m.normals[i], glm::dvec3(0, 0, -1)) < 1e-6) {
            EXPECT_NEAR(m.positions[i].z, 2.0, 1e-6);
            ++found;
        }
    EXPECT_EQ(found, 4);
    // Outward: each face normal points away from the centre (1, 2, 3).
    for (size_t t = 0; t < 12; ++t)
        EXPECT_GT(glm::dot(faceNormal(m, t), m.positions[m.indices[3 * t]] - glm::dvec3(1, 2, 3)), 0.0);
}

std::string errorOf(const fs::path& p) {
    try {
        loadGltfMesh(p, kWhere);
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace

TEST(GltfMesh, CubeWithNodeHierarchy) { checkCube(loadGltfMesh(kData / "cube.gltf", kWhere)); }

TEST(GltfMesh, BinaryGlb) { checkCube(loadGltfMesh(kData / "cube.glb", kWhere)); }

TEST(GltfMesh, ComputedNormalsAndMirroredNode) {
    // Four unshared triangles, no NORMAL, no indices, under a node that mirrors x.
    Mesh m = loadGltfMesh(kData / "tetra_mirrored.gltf", kWhere);
    ASSERT_EQ(m.positions.size(), 12u);
    ASSERT_EQ(m.indices.size(), 12u);
    expectFlatFacesAgree(m);
    for (size_t t = 0; t < 4; ++t) {
        glm::dvec3 centroid = (m.positions[m.indices[3 * t]] + m.positions[m.indices[3 * t + 1]] +
                               m.positions[m.indices[3 * t + 2]]) / 3.0;
        EXPECT_GT(glm::dot(faceNormal(m, t), centroid), 0.0) << "face " << t << " must still face outwards";
    }
    // The mirror really happened: the file's vertex (1, 1, 1) is now at (-1, 1, 1).
    bool mirrored = false;
    for (const auto& p : m.positions) mirrored |= glm::distance(p, glm::dvec3(-1, 1, 1)) < 1e-9;
    EXPECT_TRUE(mirrored);
}

TEST(GltfMesh, ErrorsNameTheKeyAndThePath) {
    struct Case {
        const char* file;
        const char* message;
    } cases[] = {
        {"missing.gltf", "missing.gltf' not found"},
        {"not_gltf.gltf", "not_gltf.gltf' is not valid glTF"},
        {"model.obj", "model.obj' is not glTF: expected a .gltf or .glb file"},
        {"strip.gltf", "strip.gltf': mesh 0 primitive 0: mode 5 is not TRIANGLES"},
        {"spectra", "is a folder, not a file"},
    };
    for (const auto& c : cases) {
        std::string what = errorOf(kData / c.file);
        EXPECT_NE(what.find("scene.json: objects.7.mesh: "), std::string::npos) << what;
        EXPECT_NE(what.find(c.message), std::string::npos) << what;
    }
}

// Indices of floats, or of a component type glTF does not define, are named as such — not as an
// accessor reading past its buffer (issue 30, second-round leftover).
TEST(GltfMesh, AnAccessorOfTheWrongComponentTypeIsNamedAsSuch) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("metamer-gltf-types-{}", ::getpid());
    fs::create_directories(dir);
    // Three float positions (36 bytes) then three indices as 4-byte floats, base64 in a data URI.
    const std::string buffer =
        "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAgD8AAABA";
    for (const auto& [type, message] : std::vector<std::pair<int, std::string>>{
             {5126, "accessor 1 has component type 5126 (float); expected indices of unsigned byte, short or int"},
             {5130, "accessor 1 has component type 5130 (not a glTF component type); expected indices of"}}) {
        const fs::path p = dir / fmt::format("indices-{}.gltf", type);
        std::ofstream(p) << fmt::format(
            R"({{"asset": {{"version": "2.0"}},
  "buffers": [{{"byteLength": 48, "uri": "data:application/octet-stream;base64,{}"}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 12}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
                {{"bufferView": 1, "componentType": {}, "count": 3, "type": "SCALAR"}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}],
  "nodes": [{{"mesh": 0}}], "scenes": [{{"nodes": [0]}}], "scene": 0}})",
            buffer, type);
        const std::string what = errorOf(p);
        EXPECT_NE(what.find("mesh 0 primitive 0 indices: " + message), std::string::npos) << what;
    }
}

namespace {

// A glTF whose default scene is `nodes` nodes instancing one mesh of `vertices` vertices (a fan
// of triangles in z = 0), its buffer in a .bin beside it; `childrenOfFirst` lists node 1 that many
// times under node 0 (a hostile file).
fs::path instancedGltf(const fs::path& dir, const std::string& name, size_t nodes, size_t vertices,
                       int childrenOfFirst = 0) {
    fs::create_directories(dir);
    std::vector<float> xyz(3 * vertices);
    for (size_t i = 0; i < vertices; ++i) {
        xyz[3 * i] = i == 0 ? 0.0f : float(std::cos(i * 0.001));
        xyz[3 * i + 1] = i == 0 ? 0.0f : float(std::sin(i * 0.001));
    }
    std::ofstream(dir / (name + ".bin"), std::ios::binary)
        .write(reinterpret_cast<const char*>(xyz.data()), std::streamsize(xyz.size() * sizeof(float)));
    std::string nodeList, sceneNodes;
    for (size_t n = 0; n < nodes; ++n) {
        std::string children;
        if (n == 0 && childrenOfFirst > 0)
            for (int c = 0; c < childrenOfFirst; ++c) children += c ? ", 1" : "1";
        nodeList += fmt::format("{}{{\"mesh\": 0, \"translation\": [{}, 0, 0]{}}}", n ? ", " : "", n,
                                children.empty() ? "" : ", \"children\": [" + children + "]");
        if (childrenOfFirst == 0 || n == 0) sceneNodes += fmt::format("{}{}", sceneNodes.empty() ? "" : ", ", n);
    }
    const fs::path p = dir / (name + ".gltf");
    std::ofstream(p) << fmt::format(
        R"({{"asset": {{"version": "2.0"}},
  "buffers": [{{"byteLength": {0}, "uri": "{1}.bin"}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": {0}}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": {2}, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "mode": 4}}]}}],
  "nodes": [{3}], "scenes": [{{"nodes": [{4}]}}], "scene": 0}})",
        xyz.size() * sizeof(float), name, vertices - vertices % 3, nodeList, sceneNodes);
    return p;
}

}  // namespace

// Instancing makes a small file into any number of triangles: what the default scene expands to
// is counted before anything is decoded and refused above the memory an input may take; a child
// listed many times (which multiplied the instances at every level) is refused; and many
// instances of one mesh decode it once (issue 30, second-round leftover: 300 000 instances took
// minutes and 2.6 GB).
TEST(GltfMesh, InstancingIsCountedBeforeItIsExpanded) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("metamer-gltf-instances-{}", ::getpid());
    // 3 000 instances of 30 vertices: loads, each instance in place.
    const GltfModel ok = loadGltf(instancedGltf(dir, "ok", 3000, 30), kWhere);
    ASSERT_EQ(ok.meshes.size(), 3000u);
    EXPECT_DOUBLE_EQ(ok.meshes[2999].positions[0].x, 2999.0);
    // Enough instances of 9 999 vertices to pass this machine's limit, whatever its memory.
    const size_t vertices = 9999;
    const size_t nodes = size_t(double(decodedImageLimitBytes()) / (2.0 * 100.0 * vertices)) + 100;
    std::string what = errorOf(instancedGltf(dir, "big", nodes, vertices));
    EXPECT_NE(what.find(fmt::format("its default scene expands to {} triangles in {} mesh instances", nodes * vertices / 3,
                                    nodes)),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("a quarter of its memory"), std::string::npos) << what;
    what = errorOf(instancedGltf(dir, "twice", 2, 3, 1000));
    EXPECT_NE(what.find("node 1 is reached twice"), std::string::npos) << what;
}
