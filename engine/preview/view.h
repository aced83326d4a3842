// One view of the preview: the scene under one set of settings (a RenderJob: --set overrides,
// grid, representation mode, detector, adaptation, display), drawn as `metamer render --write png`
// draws it: the response pass and the tonemap pass (render/display_frame.h), never the bands. The
// probe draws the bands of its pixel only (a 1×1 tile of the spectral pass); saving draws the whole
// cube. The split view holds two.
#pragma once

#include "color/tonemap.h"
#include "preview/probe.h"
#include "render/render_job.h"
#include "render/display_frame.h"
#include "render/render_setup.h"
#include "render/spectral_pass.h"
#include "spectral/cube.h"
#include "vk/context.h"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace metamer::preview {

struct ViewTimings {
    double shading_ms = 0;  // the response pass: the detector's channels
    double tonemap_ms = 0;  // tonemap pass and the read-back of its display image
    double probe_ms = 0;    // the last probe: its pixel's bands drawn and read back
    double cube_ms = 0;     // the whole cube (for saving) drawn and read back, when it happens
    double build_ms = 0;    // the last (re)build: scene load, spectra, plan, GPU objects
};

class View {
public:
    // Loads job.scene with the job's settings and makes the GPU passes. Throws Error.
    View(vk::Context& ctx, const RenderJob& job);
    ~View();

    // Takes new settings. A change of detector, adaptation, display, bits or integration remakes
    // the display plan and the display frame (the responses are the detector's); any other change
    // (overrides, grid, mode) loads the scene again as well. On an error the view keeps its old
    // settings and frame.
    void update(const RenderJob& job);
    // Loads the scene file again with the same settings (it changed on disk).
    void reload();

    // The camera of the next render(); its width and height are taken from the scene.
    void setCamera(const Camera& camera);
    // Draws the scene's responses and tonemaps them: image() is the new frame.
    void render();
    bool rendered() const { return rendered_; }

    const DisplayImage& image() const { return image_; }
    const SpectralCube& cube();  // the last frame's cube, every band (drawn on first use after render())
    // Pixel (x, y) of the last frame: its bands drawn alone (the same camera; the same values as the
    // whole cube's pixel up to float rounding), read against image().
    ProbeReadout probe(int x, int y);

    // Writes <stem>.exr (the cube, as `metamer render` writes it) and <stem>.png (the display
    // counts); returns the paths with one line each on what they hold.
    std::vector<std::pair<std::filesystem::path, std::string>> save(const std::filesystem::path& stem);

    const RenderJob& job() const { return job_; }
    const Scene& scene() const { return loaded_->scene; }
    const Grid& grid() const { return loaded_->grid; }  // the render grid
    const LoadedScene& loaded() const { return *loaded_; }
    const TonemapPlan& plan() const { return *plan_; }
    const SpectralPassPlan& passPlan() const { return frame_->passPlan(); }
    const ViewTimings& timings() const { return timings_; }
    int width() const { return loaded_->scene.camera.width; }
    int height() const { return loaded_->scene.camera.height; }

private:
    void build(const RenderJob& job);  // everything, strong guarantee
    void buildDisplay(const RenderJob& job);

    vk::Context& ctx_;
    RenderJob job_;
    // The band passes, made on first use: every band of one pixel (the probe), of the image (cube()).
    SpectralPass& bandPass(std::unique_ptr<SpectralPass>& pass, bool probe);

    // Declared in dependency order: the passes read the plan and the scene (destroyed in reverse).
    std::unique_ptr<LoadedScene> loaded_;
    std::unique_ptr<TonemapPlan> plan_;
    std::unique_ptr<DisplayFrame> frame_;
    std::unique_ptr<SpectralPass> probePass_, cubePass_;
    Camera camera_;
    bool hasCamera_ = false;
    bool rendered_ = false;
    DisplayImage image_;
    SpectralCube cube_;
    bool cubeFresh_ = false;
    ViewTimings timings_;
};

// The settings that only the display path reads (a change needs no new spectral pass).
bool sameSpectralSettings(const RenderJob& a, const RenderJob& b);

}  // namespace metamer::preview
