// The spectral pass's packing (render/spectral_packing.h), without a GPU: where each band, light
// and material value lands in the uniform blocks of shaders/interface.h, and the vertex arrays.
#include "render/spectral_packing.h"

#include "support/scene_builders.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace metamer;
using namespace metamer::test;

namespace {

Scene threeLights(const Grid& grid) {
    Scene s = emptyScene(grid, orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 1.0, 4, 4));
    s.materials.push_back(lambertian(gaussianSpectrum(550, 60, 0.8, 300, 800, 5)));
    s.materials.push_back(lambertian(0.25, "grey"));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 2, 2));
    // Given point, directional, ambient: packed ambient, directional, point.
    s.lights.push_back(pointLight({1, 2, 3}, constantSpectrum(1.0), 2.0));
    s.lights.push_back(directionalLight({0, 0, -2}, constantSpectrum(1.0), 3.0));
    s.lights.push_back(ambientLight(constantSpectrum(1.0), 4.0));
    return s;
}

}  // namespace

TEST(SpectralPacking, ScattersBandsFourToAVec4ThirtyTwoToAPass) {
    std::vector<double> v(89);
    for (size_t b = 0; b < v.size(); ++b) v[b] = double(b) + 0.5;
    glm::vec4 block[MAX_OUTPUTS];
    scatterBands(v, 2, block);  // bands 64..95: 64..88 exist
    for (int k = 0; k < MAX_OUTPUTS; ++k)
        for (int c = 0; c < 4; ++c) {
            const size_t b = 64 + size_t(k) * 4 + size_t(c);
            EXPECT_EQ(block[k][c], b < v.size() ? float(v[b]) : 0.0f) << k << "," << c;
        }
}

TEST(SpectralPacking, LightsAreSortedByKindWithTheirVectors) {
    const Scene s = threeLights(Grid{300, 740, 5});
    const SceneOnGrid g = onGrid(s);
    const PackedScene p = pack(s, g, 3, LocalFrame{});
    EXPECT_EQ(p.ambient, 1);
    EXPECT_EQ(p.directional, 1);
    EXPECT_EQ(p.point, 1);
    // Slot 0 ambient (no vector), 1 directional (towards the light), 2 point (its position, w = 1).
    EXPECT_EQ(p.lights.lights[1].vector, glm::vec4(0, 0, 1, 0));
    EXPECT_EQ(p.lights.lights[2].vector, glm::vec4(1, 2, 3, 1));
    // Each slot's spectrum is that light's E = spectrum × scale, in every pass.
    ASSERT_EQ(p.lightSpectra.size(), 3u);
    for (int pass = 0; pass < 3; ++pass) {
        EXPECT_EQ(p.lightSpectra[size_t(pass)].lightBands[0 * MAX_OUTPUTS][0], 4.0f);  // ambient
        EXPECT_EQ(p.lightSpectra[size_t(pass)].lightBands[1 * MAX_OUTPUTS][0], 3.0f);  // directional
        EXPECT_EQ(p.lightSpectra[size_t(pass)].lightBands[2 * MAX_OUTPUTS][0], 2.0f);  // point
    }
    EXPECT_EQ(p.lightSpectra[2].lightBands[0 * MAX_OUTPUTS + 7][0], 0.0f);  // band 92: past the grid
}

TEST(SpectralPacking, MaterialsArePerPassAndMaterial) {
    const Scene s = threeLights(Grid{300, 740, 5});
    const SceneOnGrid g = onGrid(s);
    const PackedScene p = pack(s, g, 3, LocalFrame{});
    ASSERT_EQ(p.materials.size(), 3u * 2u);
    for (int pass = 0; pass < 3; ++pass)
        for (size_t m = 0; m < 2; ++m) {
            const gpu::GpuMaterialBlock& b = p.materials[size_t(pass) * 2 + m];
            for (int k = 0; k < MAX_OUTPUTS; ++k)
                for (int c = 0; c < 4; ++c) {
                    const size_t band = size_t(pass) * BANDS_PER_PASS + size_t(k) * 4 + size_t(c);
                    EXPECT_EQ(b.diffuse[k][c], band < 89 ? float(g.materials[m].diffuse[band]) : 0.0f);
                }
            EXPECT_EQ(b.switches.x & MATERIAL_FLUORESCENT, 0u);    // not fluorescent
            EXPECT_EQ(b.params.y, float(pass * MAX_OUTPUTS));    // first texture layer of the pass
        }
}

TEST(SpectralPacking, VerticesCarryTheMeshAndFaceNormalsWhereItHasNone) {
    Scene s = threeLights(Grid{400, 700, 10});
    Mesh bare = quad({0, 0, 1}, {0, 0, 1}, 1, 1);
    bare.normals.clear();  // no normals: every triangle gets its own three face-normal vertices
    s.meshes.push_back(bare);
    const PackedScene p = pack(s, onGrid(s), 1, LocalFrame{});
    ASSERT_EQ(p.draws.size(), 2u);
    EXPECT_EQ(p.draws[0].indexCount, 6u);
    EXPECT_EQ(p.draws[1].indexCount, 6u);
    const gpu::SpectralVertex& v0 = p.vertices[0];
    EXPECT_EQ(v0.position[2], 0.0f);
    EXPECT_EQ(v0.normal[2], 1.0f);
    // The bare quad: 4 vertices as given (no normal), then 2 × 3 with the face normal.
    ASSERT_EQ(p.vertices.size(), 4u + 4u + 6u);
    for (size_t i = 8; i < 14; ++i) EXPECT_NEAR(p.vertices[i].normal[2], 1.0f, 1e-7f) << i;
    EXPECT_EQ(p.draws[1].vertexOffset, 4);
}

TEST(SpectralPacking, RefusesALightBeyondFloat32) {
    Scene s = threeLights(Grid{400, 700, 10});
    s.lights[0].scale = 1e39;
    try {
        pack(s, onGrid(s), 1, LocalFrame{});
        ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(std::string(e.what()).find("beyond the largest float32"), std::string::npos) << e.what();
    }
}

// The response pass sums its per-band terms only over the band layers where the detector has a
// nonzero weight (SPEC_RESPONSE_FIRST_LAYER, SPEC_RESPONSE_END_LAYER): on 300–740 nm, a detector
// that sees 360–700 nm only spans layers 3 (360–375 nm) to 20 (700–715 nm).
TEST(SpectralPacking, ResponseLayersSpanTheDetectorsNonzeroWeights) {
    const Scene s = threeLights(Grid{300, 740, 5});
    const SceneOnGrid g = onGrid(s);
    const size_t n = g.wavelengths_nm.size();
    std::vector<std::vector<double>> weights(3, std::vector<double>(n, 0.0));
    for (size_t b = 0; b < n; ++b) {
        const double nm = g.wavelengths_nm[b];
        if (nm >= 360 && nm <= 700) weights[b % 3][b] = 1.0;  // each band seen by one channel
    }
    const PackedScene p = packResponses(s, g, weights, LocalFrame{});
    EXPECT_EQ(p.responseChannels, 3);
    EXPECT_EQ(p.responseFirstLayer, 3);   // band 12 (360 nm) / 4
    EXPECT_EQ(p.responseEndLayer, 21);    // band 80 (700 nm) / 4 + 1
    std::vector<std::vector<double>> none(1, std::vector<double>(n, 0.0));
    const PackedScene blind = packResponses(s, g, none, LocalFrame{});
    EXPECT_EQ(blind.responseFirstLayer, 0);
    EXPECT_EQ(blind.responseEndLayer, 0);
}
