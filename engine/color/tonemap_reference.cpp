#include "color/tonemap.h"

#include "core/cpu_count.h"

#include <thread>

namespace metamer {

DisplayImage tonemapReference(const TonemapPlan& plan, const SpectralCube& cube) {
    DisplayImage img;
    img.width = cube.width;
    img.height = cube.height;
    img.channels = int(plan.detector.weights.size());
    size_t n = size_t(cube.width) * cube.height;
    bool colorimetric = plan.mode != TonemapMode::ResponsesOnly;
    img.responses.resize(n * img.channels);
    if (colorimetric) {
        img.xyz.resize(n * 3);
        img.counts.resize(n * 3);
        img.clipped.resize(n);
    }
    std::vector<size_t> clipped(size_t(usableCpuCount()), 0);
    auto rows = [&](int t, int y0, int y1) {
        std::vector<double> r(img.channels);
        for (int y = y0; y < y1; ++y)
            for (int x = 0; x < cube.width; ++x) {
                size_t i = size_t(y) * cube.width + x;
                glm::dvec3 xyz = relativeXyz(plan, cube.pixel(x, y), r.data());
                for (int c = 0; c < img.channels; ++c) img.responses[i * img.channels + c] = float(r[c]);
                if (!colorimetric) continue;
                for (int c = 0; c < 3; ++c) img.xyz[3 * i + c] = float(xyz[c] * plan.xyzOutputScale);
                EncodeResult e = encodeXyz(plan.display, plan.adaptation * xyz);
                for (int c = 0; c < 3; ++c) img.counts[3 * i + c] = uint16_t(e.counts[c]);
                img.clipped[i] = e.clipped;
                clipped[t] += e.clipped;
            }
    };
    int threads = int(clipped.size());
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back(rows, t, cube.height * t / threads, cube.height * (t + 1) / threads);
    for (auto& t : pool) t.join();
    for (size_t c : clipped) img.clippedPixels += c;
    return img;
}

}  // namespace metamer
