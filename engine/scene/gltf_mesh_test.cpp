#include "scene/gltf_mesh.h"

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
