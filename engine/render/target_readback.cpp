#include "render/target_readback.h"

#include "core/cpu_count.h"

#include <algorithm>
#include <cstring>
#include <thread>
#include <vector>

namespace metamer {

void readLayered(const LayeredView& a, int ssaa, SpectralCube& cube) {
    const int s = ssaa, bands = cube.bands(), W = cube.width, H = cube.height, layers = (bands + 3) / 4;
    auto copyRows = [&](int y0, int y1) {
        // One layer row at a time: 4 bands of every pixel, strided into the cube.
        for (int y = y0; y < y1; ++y)
            for (int l = 0; l < layers; ++l) {
                const float* row = a.row(uint32_t(l), uint32_t(y));
                int n = std::min(4, bands - 4 * l);
                float* out = cube.pixel(0, y) + 4 * l;
                if (n == 4)
                    for (int x = 0; x < W; ++x, out += bands) std::memcpy(out, row + 4 * x, 16);
                else
                    for (int x = 0; x < W; ++x, out += bands) std::memcpy(out, row + 4 * x, 4 * size_t(n));
            }
    };
    auto filterRows = [&](int y0, int y1) {
        const float norm = 1.0f / float(s * s);
        std::vector<float> acc(size_t(W) * 4);
        for (int y = y0; y < y1; ++y)
            for (int l = 0; l < layers; ++l) {
                std::fill(acc.begin(), acc.end(), 0.0f);
                for (int sy = 0; sy < s; ++sy) {
                    const float* row = a.row(uint32_t(l), uint32_t(y * s + sy));
                    for (int x = 0; x < W; ++x)
                        for (int sx = 0; sx < s; ++sx)
                            for (int c = 0; c < 4; ++c) acc[size_t(x) * 4 + c] += row[(x * s + sx) * 4 + c];
                }
                int n = std::min(4, bands - 4 * l);
                for (int x = 0; x < W; ++x)
                    for (int c = 0; c < n; ++c) cube.at(x, y, 4 * l + c) = acc[size_t(x) * 4 + c] * norm;
            }
    };
    int threads = std::max(1, std::min(usableCpuCount(), H));
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) {
        int y0 = H * t / threads, y1 = H * (t + 1) / threads;
        if (s == 1)
            pool.emplace_back(copyRows, y0, y1);
        else
            pool.emplace_back(filterRows, y0, y1);
    }
    for (auto& t : pool) t.join();
}

}  // namespace metamer
