// Reading the layered target into a cube (render/target_readback.h), without a GPU: a synthetic
// target in host memory with padded rows and layers.
#include "render/target_readback.h"

#include <gtest/gtest.h>

#include <vector>

using namespace metamer;

namespace {

// A target of w × h texels and `layers` layers, 4 floats a texel, with `pad` spare bytes after
// each row and each layer; texel (x, y) of layer l, component c holds value(l, x, y, c).
struct FakeTarget {
    std::vector<char> bytes;
    LayeredView view;
    FakeTarget(int w, int h, int layers, size_t pad, float (*value)(int, int, int, int)) {
        view.rowPitch = size_t(w) * 16 + pad;
        view.layerPitch = view.rowPitch * size_t(h) + pad;
        bytes.assign(view.layerPitch * size_t(layers), 0);
        view.base = bytes.data();
        for (int l = 0; l < layers; ++l)
            for (int y = 0; y < h; ++y) {
                float* row = reinterpret_cast<float*>(bytes.data() + size_t(l) * view.layerPitch + size_t(y) * view.rowPitch);
                for (int x = 0; x < w; ++x)
                    for (int c = 0; c < 4; ++c) row[x * 4 + c] = value(l, x, y, c);
            }
    }
};

float code(int l, int x, int y, int c) { return float(1000 * y + 100 * x + 4 * l + c); }

}  // namespace

TEST(TargetReadback, CopiesEveryBandOfEveryPixelAtOneSample) {
    const Grid grid{400, 450, 5};  // 11 bands: 3 layers, the last holding 3 bands
    SpectralCube cube(5, 3, grid);
    FakeTarget t(5, 3, 3, 48, code);
    readLayered(t.view, 1, cube);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x)
            for (int b = 0; b < 11; ++b) ASSERT_EQ(cube.at(x, y, b), code(b / 4, x, y, b % 4)) << x << "," << y << "," << b;
}

TEST(TargetReadback, BoxFiltersSsaaSamples) {
    const Grid grid{400, 430, 10};  // 4 bands: one layer
    const int s = 3;
    SpectralCube cube(2, 2, grid);
    FakeTarget t(2 * s, 2 * s, 1, 16, code);
    readLayered(t.view, s, cube);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x)
            for (int b = 0; b < 4; ++b) {
                double sum = 0;
                for (int sy = 0; sy < s; ++sy)
                    for (int sx = 0; sx < s; ++sx) sum += code(0, x * s + sx, y * s + sy, b);
                ASSERT_NEAR(cube.at(x, y, b), sum / (s * s), 1e-3) << x << "," << y << "," << b;
            }
}
