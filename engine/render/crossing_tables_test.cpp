// Single-crossing tables (render/crossing_tables.h), without a GPU: the rows packResponses writes,
// read back by the shader's interpolation (mirrored in C++), against the response summed band by
// band in double, within the certified bound — for a detector with a negative lobe too.
#include "render/crossing_tables.h"

#include "scene/shapes.h"
#include "support/scene_builders.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace metamer;
using namespace metamer::test;

TEST(CrossingTables, InterpolateEveryChannelWithinTheCertifiedBound) {
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
    const CrossingAxes axes = crossingAxes(p, g, p.responseFirstLayer, p.responseEndLayer);
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
