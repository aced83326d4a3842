#include "preview/view.h"

#include "core/timing.h"
#include "render/outputs.h"

#include <fmt/ranges.h>

#include <chrono>

namespace metamer::preview {

namespace {
// What the window shows and the probe reads of a frame: the counts (XYZ comes from the probe's own
// bands, in double).
constexpr TonemapOutputs kShown{true, false, false};
}  // namespace

bool sameSpectralSettings(const RenderJob& a, const RenderJob& b) {
    return a.scene == b.scene && a.overrides == b.overrides && a.grid == b.grid && a.mode == b.mode &&
           a.coverage == b.coverage && a.ssaa == b.ssaa && a.allowOutsidePaths == b.allowOutsidePaths;
}

View::View(vk::Context& ctx, const RenderJob& job) : ctx_(ctx) { build(job); }

View::~View() = default;

void View::build(const RenderJob& job) {
    auto t0 = Clock::now();
    std::unique_ptr<LoadedScene> loaded = loadJobScene(job);
    OutputFiles files;
    TonemapSettings settings = tonemapSettings(job, loaded->scene, &files);
    auto plan = std::make_unique<TonemapPlan>(makeJobTonemapPlan(job, *loaded, settings));
    if (plan->mode == TonemapMode::ResponsesOnly)
        failInput(Where{"", "--detector"}, "detector {} gives responses only (no display path); the preview shows "
                  "display images: choose an observer, a camera or a film", plan->detector.name);
    SpectralPassOptions po;
    po.ssaa = job.ssaa;
    auto frame = std::make_unique<DisplayFrame>(ctx_, loaded->scene, loaded->rendered, *plan, po, kShown);
    // Keep the user's camera when the image size allows (the view survives a reload).
    if (hasCamera_) {
        Camera c = camera_;
        c.width = loaded->scene.camera.width;
        c.height = loaded->scene.camera.height;
        frame->setCamera(c);
        camera_ = c;
    }
    // Swap in, dependants first.
    frame_.reset();
    probePass_.reset();
    cubePass_.reset();
    plan_ = std::move(plan);
    loaded_ = std::move(loaded);
    frame_ = std::move(frame);
    job_ = job;
    rendered_ = false;
    cubeFresh_ = false;
    timings_.build_ms = msSince(t0);
}

void View::buildDisplay(const RenderJob& job) {
    auto t0 = Clock::now();
    OutputFiles files;
    TonemapSettings settings = tonemapSettings(job, loaded_->scene, &files);
    auto plan = std::make_unique<TonemapPlan>(makeJobTonemapPlan(job, *loaded_, settings));
    if (plan->mode == TonemapMode::ResponsesOnly)
        failInput(Where{"", "--detector"}, "detector {} gives responses only (no display path); the preview shows "
                  "display images: choose an observer, a camera or a film", plan->detector.name);
    SpectralPassOptions po;
    po.ssaa = job.ssaa;
    auto frame = std::make_unique<DisplayFrame>(ctx_, loaded_->scene, loaded_->rendered, *plan, po, kShown);
    if (hasCamera_) frame->setCamera(camera_);
    frame_ = std::move(frame);  // the old frame (which reads the old plan) goes first
    plan_ = std::move(plan);
    job_ = job;
    rendered_ = false;  // the band passes stay: their bands do not depend on the display
    timings_.build_ms = msSince(t0);
}

void View::update(const RenderJob& job) {
    if (sameSpectralSettings(job, job_)) buildDisplay(job);
    else build(job);
}

void View::reload() { build(job_); }

void View::setCamera(const Camera& camera) {
    Camera c = camera;
    c.width = loaded_->scene.camera.width;
    c.height = loaded_->scene.camera.height;
    frame_->setCamera(c);
    if (probePass_) probePass_->setCamera(c);
    if (cubePass_) cubePass_->setCamera(c);
    camera_ = c;
    hasCamera_ = true;
}

void View::render() {
    image_ = frame_->render();
    timings_.shading_ms = frame_->timings().shading_ms;
    timings_.tonemap_ms = frame_->timings().tonemap_ms;
    rendered_ = true;
    cubeFresh_ = false;
}

SpectralPass& View::bandPass(std::unique_ptr<SpectralPass>& pass, bool probe) {
    if (!pass) {
        SpectralPassOptions po;
        po.ssaa = job_.ssaa;
        if (probe) po.stripRows = po.tileColumns = 1;
        pass = std::make_unique<SpectralPass>(ctx_, loaded_->scene, loaded_->rendered, po);
        if (hasCamera_) pass->setCamera(camera_);
    }
    return *pass;
}

const SpectralCube& View::cube() {
    if (!cubeFresh_) {
        if (!rendered_) render();
        auto t0 = Clock::now();
        SpectralPass& pass = bandPass(cubePass_, false);
        pass.draw();
        pass.readback(cube_);
        timings_.cube_ms = msSince(t0);
        cubeFresh_ = true;
    }
    return cube_;
}

ProbeReadout View::probe(int x, int y) {
    if (!rendered_) render();
    if (x < 0 || y < 0 || x >= width() || y >= height())
        failRuntime("probe at {},{} is outside the {}×{} image", x, y, width(), height());
    auto t0 = Clock::now();
    SpectralPass& pass = bandPass(probePass_, true);
    pass.setTile(x, y);
    pass.draw();
    SpectralCube pixel;
    pass.readback(pixel);
    ProbeReadout p = probePixel(*plan_, loaded_->representation, pixel.pixel(0, 0), pixel.grid, image_, x, y);
    timings_.probe_ms = msSince(t0);
    return p;
}

std::vector<std::pair<std::filesystem::path, std::string>> View::save(const std::filesystem::path& stem) {
    SpectralCube c = cube();
    const Representation& rep = loaded_->representation;
    projectCube(rep, c.data, c.bands());  // linear:K: as `metamer render` writes it
    Attributes provenance = renderProvenance(job_.scene.string(), "gpu", loaded_->grid, rep);
    provenance.push_back({"metamer:preview", "saved from metamer preview"});
    OutputTargets targets;
    targets.cube = stem;
    targets.cube += ".exr";
    targets.png = stem;
    targets.png += ".png";
    RenderOutputs out(targets, c.width, c.height, loaded_->grid, rep, plan_.get(), provenance);
    out.writeRows(0, c.height, c.data.data(), &image_);
    out.writeQuickLook(c, loaded_->library);  // only for a detector without a display path
    std::vector<std::pair<std::filesystem::path, std::string>> written;
    for (const WrittenFile& f : out.commit()) written.push_back({f.path, f.what});
    return written;
}

}  // namespace metamer::preview
