#include "app/preview_command.h"

#include "app/cli_checks.h"
#include "app/render_flags.h"

#include "core/error.h"
#include "preview/preview.h"

#include <cstdio>

namespace metamer {

CLI::App* addPreviewCommand(CLI::App& app, PreviewArgs& a) {
    auto* c = app.add_subcommand("preview",
                                 "open a window with the scene's display image and live controls (docs/preview.md)");
    c->add_option("scene", a.scene, "scene file (JSON, docs/scene-format.md)")->required();
    addRenderFlags(c, a.render, kSceneFlags | kSpectralFlags | kDisplayFlags | kSamplingFlags | kDeviceFlags);
    c->add_option("--split", a.split,
                  "show a second view to the right with this change: KEY=VALUE (a --set), or detector=, adapt=, "
                  "display=, mode=, grid=")
        ->take_all();
    c->add_option("--frames", a.frames,
                  "render N frames without waiting for input, print the median frame time and close")
        ->check(CLI::Range(1, 100000));
    c->add_option("--screenshot", a.screenshot,
                  "write the last frame's view region(s) as shown, an 8-bit PNG at the scene's size");
    c->add_option("--window-screenshot", a.windowScreenshot, "write the last frame's whole window, UI included");
    c->add_option("--probe", a.probe, "probe pixel X,Y (row 0 at the top), as if the cursor were there");
    c->add_option("--pin", a.pin, "pin the second probe at pixel X,Y");
    c->add_option("--out,-o", a.out, "folder that Save (S) writes into")->check(outputFolder())->capture_default_str();
    c->add_flag("--save", a.save, "save each view's cube and PNG when the window closes");
    c->add_flag("--no-watch", a.noWatch, "do not reload the scene file when it changes on disk");
    return c;
}

int runPreviewCommand(const PreviewArgs& a) {
    preview::PreviewOptions o;
    RenderJob& job = o.job;
    job.scene = a.scene;
    applyRenderSettings(a.render, job, [](const std::string& name) { return "--" + name; });
    o.split = a.split;
    o.frames = a.frames;
    o.screenshot = a.screenshot;
    o.windowScreenshot = a.windowScreenshot;
    o.outDir = a.out;
    o.saveAtEnd = a.save;
    if (!a.probe.empty()) o.probe = preview::parsePixel(a.probe, "--probe");
    if (!a.pin.empty()) o.pin = preview::parsePixel(a.pin, "--pin");
    o.watch = !a.noWatch;

    preview::PreviewReport r = preview::runPreview(o);
    if (r.frames > 0) {
        std::printf("preview: %d×%d px, %d bands, on %s (present mode %s)\n", r.width, r.height, r.bands,
                    r.device.c_str(), r.presentMode.c_str());
        std::printf("%s\n", r.views.c_str());
        std::printf("views built in %.0f ms (scene, spectra, display plan, GPU passes: the cost of a light, mode "
                    "or grid change)\n", r.build_ms);
        std::printf("frames: %d; first frame %.1f ms (includes shader compilation)", r.frames, r.first_ms);
        if (r.frames > 1)
            std::printf("; median of the other %d: %.1f ms per frame (shading %.1f, tonemap %.1f, probe %.1f, "
                        "present %.1f)",
                        r.frames - 1, r.median_ms, r.medianShading_ms, r.medianTonemap_ms, r.medianProbe_ms,
                        r.medianPresent_ms);
        std::printf("\n");
    }
    for (const auto& p : r.probes) std::printf("%s\n", p.c_str());
    for (const auto& w : r.written) std::printf("wrote %s (%s)\n", w.first.c_str(), w.second.c_str());
    for (const auto& n : r.notes) std::printf("note: %s\n", n.c_str());
    if (r.validationErrors) {
        std::fprintf(stderr, "metamer: %u Vulkan validation error(s) (see above)\n", r.validationErrors);
        return int(ExitCode::Failure);
    }
    return 0;
}

}  // namespace metamer
