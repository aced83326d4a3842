// The spectral pass's packing (render/spectral_packing.h), without a GPU: where each band, light
// and material value lands in the uniform blocks of shaders/interface.h, and the vertex arrays.
#include "render/spectral_packing.h"

#include "render/crossing_tables.h"
#include "scene/shapes.h"

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

// Single-crossing tables (render/crossing_tables.h): the rows packResponses writes, read back by the
// shader's interpolation (mirrored in C++), against the response summed band by band in double,
// within the certified bound — for a detector with a negative lobe too.
TEST(SpectralPacking, CrossingTablesInterpolateEveryChannelWithinTheCertifiedBound) {
    Scene s = emptyScene(Grid{300, 740, 5}, orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 2.0, 4, 4));
    s.materials.push_back(lambertian(gaussianSpectrum(560, 80, 0.9, 300, 800, 5), "card"));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 2, 2, 0));
    s.lights.push_back(directionalLight({0.2, -0.3, -1}, gaussianSpectrum(520, 150, 1.0, 300, 800, 5), 2.0));
    s.lights.back().shadows = true;
    s.lights.push_back(ambientLight(constantSpectrum(1.0), 0.5));
    // A deep gel (τ down to 10⁻³ per sheet) and a dye block 0.4 long at up to 12 absorbance per unit.
    Spectrum gel = gaussianSpectrum(450, 30, 0.999, 300, 800, 5);
    for (double& v : gel.values) v = 1.0 - v;
    s.materials.push_back(filterSheet(gel, "gel"));
    s.meshes.push_back(quad({0, 0, 0.5}, {0, 0, 1}, 1, 1, 1));
    s.materials.push_back(absorbingMedium(gaussianSpectrum(600, 40, 12.0, 300, 800, 5), "dye"));
    Mesh box = makeBox({0.3, 0.3, 0.3}, {0.4, 0.4, 0.4});
    box.material = 2;
    s.meshes.push_back(std::move(box));
    const SceneOnGrid g = onGrid(s);
    const size_t n = g.wavelengths_nm.size();
    std::vector<std::vector<double>> weights(3, std::vector<double>(n, 0.0));
    for (size_t b = 0; b < n; ++b) {
        const double nm = g.wavelengths_nm[b];
        weights[0][b] = std::exp(-0.5 * std::pow((nm - 450) / 30, 2));
        weights[1][b] = std::exp(-0.5 * std::pow((nm - 550) / 40, 2)) - 0.3 * std::exp(-0.5 * std::pow((nm - 450) / 20, 2));
        weights[2][b] = nm >= 380 && nm <= 700 ? 1.0 : 0.0;
    }
    const PackedScene p = packResponses(s, g, weights, LocalFrame{});
    ASSERT_GE(p.crossingHeader, 0);
    const CrossingAxes axes = crossingAxes(crossingDepthBounds(p, g), p.depthSpectra, p.bandLayers, n,
                                           p.responseFirstLayer, p.responseEndLayer);
    ASSERT_EQ(axes.channels.size(), 2u);
    EXPECT_EQ(p.crossingNodes, axes.totalNodes);
    const size_t table = size_t(p.responseBlocks[0].tables.x), perValue = 1;
    // Light 0 (the ambient light sorts first), diffuse: its weighted spectrum as the records hold it.
    std::vector<std::vector<double>> r(3, std::vector<double>(n));
    for (size_t c = 0; c < 3; ++c)
        for (size_t b = 0; b < n; ++b) r[c][b] = double(float(weights[c][b] * g.materials[0].diffuse[b] * g.lights[1][b]));
    const double bound = crossingTableBound();
    EXPECT_LT(bound, 2e-6);
    for (int e = 0; e < 2; ++e) {
        const CrossingAxis& a = axes.channels[size_t(e)];
        ASSERT_GT(a.nodes, 2) << e;
        // The header row the shader reads.
        const glm::vec4 header = p.depthSpectra[size_t(p.crossingHeader + e)];
        EXPECT_FLOAT_EQ(header.x, float(1.0 / a.h));
        EXPECT_EQ(header.y, float(a.nodes - 1));
        EXPECT_EQ(header.z, float(a.first));
        const double largest = double(a.nodes - 1) * a.h;
        // The gel: 2 triangles, twice (camera and light); the box: twice its diagonal.
        EXPECT_GE(largest, e == 0 ? 4.0 : 2.0 * std::sqrt(3 * 0.16) - 1e-9) << e;
        double worst = 0.0;
        for (int q = 0; q <= 997; ++q) {
            const double x = largest * q / 997.0;
            for (int c = 0; c < 3; ++c) {
                double F = 0.0, G = 0.0;
                for (size_t b = 0; b < n; ++b) {
                    const double term = r[size_t(c)][b] * std::exp2(x * a.log2Tau[b]);
                    F += term;
                    G += std::fabs(term);
                }
                const double got = crossingTableAt(p.depthSpectra, table, axes, e, c, perValue, x);
                // The bound, and float32 storage of F and h·F' (a few ulps of G).
                worst = std::max(worst, std::fabs(got - F) / G);
                EXPECT_LE(std::fabs(got - F), (bound + 4e-7) * G) << "channel " << e << " x " << x << " detector " << c;
            }
        }
        std::printf("crossing table, channel %d: %d nodes, worst error %.2e of G (bound %.2e)\n", e, a.nodes, worst, bound);
    }
}
