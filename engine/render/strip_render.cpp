#include "render/strip_render.h"

#include "core/memory_limits.h"

#include "render/display_frame.h"
#include "render/tonemap_pass.h"

#include <fmt/ranges.h>

#include <algorithm>
#include <memory>
#include <unistd.h>

namespace metamer {

size_t defaultMemoryBudget() { return size_t(machineMemoryBytes() / 4); }

namespace {

// Display outputs only: the response pass (bands, with transparent objects) and the tonemap pass, strip by strip.
StripResult displayStrips(const StripJob& j, SpectralPassOptions po) {
    const int W = j.scene->camera.width, H = j.scene->camera.height;
    StripResult r;
    DisplayFrame frame(*j.context, *j.scene, *j.rendered, *j.plan, po, j.outputs->displayOutputs());
    r.responsePass = frame.passPlan().responses;
    r.displayOnly = true;
    r.description = j.context->deviceInfo().name + ": " + frame.passPlan().describe() +
                    fmt::format(", in strips of {} rows", frame.rows());
    const int total = (H + frame.rows() - 1) / frame.rows();
    if (j.afterStrip) j.afterStrip(0, total);
    for (int r0 = 0; r0 < H; r0 += frame.rows()) {
        const int rows = std::min(frame.rows(), H - r0);
        frame.setStrip(r0);
        const DisplayImage d = frame.render();
        r.shading_ms += frame.timings().shading_ms;
        r.tonemap_ms += frame.timings().tonemap_ms;
        // Clipped pixels of the kept rows only (rows past the image's bottom are dropped).
        for (size_t i = 0; i < size_t(W) * rows && i < d.clipped.size(); ++i) r.clippedPixels += d.clipped[i];
        j.outputs->writeRows(r0, rows, nullptr, &d);
        ++r.strips;
        if (j.afterStrip) j.afterStrip(r.strips, total);
    }
    return r;
}

}  // namespace

StripResult renderInStrips(const StripJob& j) {
    const Scene& scene = *j.scene;
    int W = scene.camera.width, H = scene.camera.height;
    SpectralPassOptions po;
    po.ssaa = j.ssaa;
    po.readback = j.readback;
    po.stripRows = j.stripRows;
    RenderOutputs& out = *j.outputs;
    if (!out.needsCube() && j.plan) return displayStrips(j, po);

    StripResult r;
    po.sampled = j.plan != nullptr;
    SpectralPass pass(*j.context, scene, *j.rendered, po);
    std::unique_ptr<TonemapPass> tonemap;
    if (j.plan) tonemap = std::make_unique<TonemapPass>(*j.context, pass, *j.plan);
    r.description = j.context->deviceInfo().name + ": " + pass.plan().describe() +
                    fmt::format(", in strips of {} rows", pass.rows());

    SpectralCube strip;
    const int total = (H + pass.rows() - 1) / pass.rows();
    if (j.afterStrip) j.afterStrip(0, total);
    for (int r0 = 0; r0 < H; r0 += pass.rows()) {
        int rows = std::min(pass.rows(), H - r0);
        pass.setStrip(r0);
        pass.draw();
        r.shading_ms += pass.timings().shading_ms;
        DisplayImage d;
        if (tonemap) {
            d = tonemap->render();
            r.tonemap_ms += tonemap->lastMs();
            // Clipped pixels of the kept rows only (rows past the image's bottom are dropped).
            for (size_t i = 0; i < size_t(W) * rows && i < d.clipped.size(); ++i) r.clippedPixels += d.clipped[i];
        }
        if (out.needsCube()) {
            pass.readback(strip);
            r.readback_ms += pass.timings().readback_ms;
            projectCube(*j.representation, strip.data, strip.bands());
        }
        out.writeRows(r0, rows, out.needsCube() ? strip.data.data() : nullptr, tonemap ? &d : nullptr);
        ++r.strips;
        if (j.afterStrip) j.afterStrip(r.strips, total);
    }
    return r;
}

}  // namespace metamer
