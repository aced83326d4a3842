#include "render/strip_render.h"

#include "io/image_file.h"
#include "io/spectral_exr.h"
#include "render/tonemap_pass.h"

#include <fmt/ranges.h>

#include <algorithm>
#include <memory>
#include <unistd.h>

namespace metamer {

size_t bytesPerRow(int width, int channels, int ssaa, bool display, int detectorChannels) {
    size_t layers = size_t(channels + 3) / 4;
    size_t perPixel = size_t(channels) * 4                          // the cube
                      + size_t(ssaa) * ssaa * layers * 16           // the layered target
                      + (display ? 4 * 16                           // the tonemap targets
                                       + 4 * 16                     // their read-back copy
                                       + (3 * 4 + 3 * 2 + size_t(detectorChannels) * 4)  // DisplayImage
                                 : 0);
    return size_t(width) * perPixel;
}

size_t defaultMemoryBudget() {
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || size <= 0) return size_t(2) << 30;
    return size_t(pages) * size_t(size) / 4;
}

StripResult renderInStrips(const StripJob& j) {
    const Scene& scene = *j.scene;
    int W = scene.camera.width, H = scene.camera.height;
    StripResult r;
    SpectralPassOptions po;
    po.ssaa = j.ssaa;
    po.readback = j.readback;
    po.sampled = j.plan != nullptr;
    po.stripRows = j.stripRows;
    SpectralPass pass(*j.context, scene, *j.rendered, po);
    std::unique_ptr<TonemapPass> tonemap;
    if (j.plan) tonemap = std::make_unique<TonemapPass>(*j.context, pass, *j.plan);
    r.description = j.context->deviceInfo().name + ": " + pass.plan().describe() +
                    fmt::format(", in strips of {} rows", pass.rows());

    // Open every output first: each appears only when complete (AtomicOutput).
    const Representation& rep = *j.representation;
    std::unique_ptr<SpectralExrWriter> cubeOut;
    std::unique_ptr<ImageFileWriter> channelsOut, pngOut, xyzOut, responsesOut;
    if (!j.cube.empty()) {
        if (rep.mode.spectral()) {
            ExrWriteOptions wo;
            wo.half = j.half;
            wo.compression = j.compression;
            wo.extraAttributes = j.provenance;
            cubeOut = std::make_unique<SpectralExrWriter>(j.cube, W, H, rep.grid, wo);
        } else {
            ImageFile f{W, H, rep.channelNames, j.provenance};
            f.attributes.push_back({"metamer:representation", rep.description});
            channelsOut = std::make_unique<ImageFileWriter>(j.cube, f, 32);
        }
    }
    if (j.plan && j.plan->mode != TonemapMode::ResponsesOnly) {
        if (!j.png.empty()) {
            ImageFile f{W, H, {"R", "G", "B"}, j.provenance};
            f.attributes.push_back({"ImageDescription", "metamer display image: " + j.plan->description});
            pngOut = std::make_unique<ImageFileWriter>(j.png, f, j.plan->display.bits);
        }
        if (!j.xyz.empty()) {
            ImageFile f{W, H, {"X", "Y", "Z"}, j.provenance};
            f.attributes.push_back({"metamer:xyz", j.plan->xyzUnits});
            f.attributes.push_back({"metamer:integration", integrationName(j.plan->detector.integration)});
            f.attributes.push_back({"metamer:display", j.plan->description});
            xyzOut = std::make_unique<ImageFileWriter>(j.xyz, f, 32);
        }
    }
    if (j.plan && !j.responses.empty()) {
        ImageFile f{W, H, j.plan->detector.channels, j.provenance};
        f.attributes.push_back({"metamer:detector", j.plan->detector.name});
        f.attributes.push_back({"metamer:units", j.plan->detector.units});
        f.attributes.push_back({"metamer:integration", integrationName(j.plan->detector.integration)});
        responsesOut = std::make_unique<ImageFileWriter>(j.responses, f, 32);
    }

    SpectralCube strip;
    bool needCube = cubeOut || channelsOut;
    for (int r0 = 0; r0 < H; r0 += pass.rows()) {
        int rows = std::min(pass.rows(), H - r0);
        pass.setStrip(r0);
        pass.draw();
        r.shading_ms += pass.timings().shading_ms;
        if (tonemap) {
            DisplayImage d = tonemap->render();
            r.tonemap_ms += tonemap->lastMs();
            // Rows past the image's bottom (the last strip) are dropped.
            auto rowsOf = [&](const auto& v, size_t perPixel) {
                using T = typename std::decay_t<decltype(v)>::value_type;
                return std::vector<T>(v.begin(), v.begin() + size_t(W) * rows * perPixel);
            };
            if (pngOut) pngOut->writeRows(r0, rows, rowsOf(d.counts, 3));
            if (xyzOut) xyzOut->writeRows(r0, rows, rowsOf(d.xyz, 3));
            if (responsesOut) responsesOut->writeRows(r0, rows, rowsOf(d.responses, size_t(d.channels)));
            // Clipped pixels of the kept rows only.
            for (size_t i = 0; i < size_t(W) * rows && i < d.clipped.size(); ++i) r.clippedPixels += d.clipped[i];
        }
        if (needCube) {
            pass.readback(strip);
            r.readback_ms += pass.timings().readback_ms;
            projectCube(rep, strip.data, strip.bands());
            if (cubeOut) cubeOut->writeRows(r0, rows, strip.data.data());
            if (channelsOut)
                channelsOut->writeRows(r0, rows, std::vector<float>(strip.data.begin(),
                                                                    strip.data.begin() + size_t(W) * rows * strip.bands()));
        }
        ++r.strips;
    }
    if (cubeOut) r.clampedToHalf = cubeOut->commit().clampedToHalfMax;
    if (channelsOut) channelsOut->commit();
    if (pngOut) pngOut->commit();
    if (xyzOut) xyzOut->commit();
    if (responsesOut) responsesOut->commit();
    return r;
}

}  // namespace metamer
