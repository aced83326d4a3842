#include "preview/view.h"

#include "core/timing.h"
#include "render/outputs.h"

#include <fmt/ranges.h>

#include <chrono>

namespace metamer::preview {

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
    po.sampled = true;  // the tonemap pass reads the target
    auto pass = std::make_unique<SpectralPass>(ctx_, loaded->scene, loaded->rendered, po);
    auto tonemap = std::make_unique<TonemapPass>(ctx_, *pass, *plan);
    // Keep the user's camera when the image size allows (the view survives a reload).
    if (hasCamera_) {
        Camera c = camera_;
        c.width = loaded->scene.camera.width;
        c.height = loaded->scene.camera.height;
        pass->setCamera(c);
        camera_ = c;
    }
    // Swap in, dependants first.
    tonemap_.reset();
    pass_.reset();
    plan_ = std::move(plan);
    loaded_ = std::move(loaded);
    pass_ = std::move(pass);
    tonemap_ = std::move(tonemap);
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
    auto tonemap = std::make_unique<TonemapPass>(ctx_, *pass_, *plan);
    tonemap_ = std::move(tonemap);  // the old pass (which reads the old plan) goes first
    plan_ = std::move(plan);
    job_ = job;
    rendered_ = false;
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
    pass_->setCamera(c);
    camera_ = c;
    hasCamera_ = true;
}

void View::render() {
    pass_->draw();
    timings_.shading_ms = pass_->timings().shading_ms;
    image_ = tonemap_->render();
    timings_.tonemap_ms = tonemap_->lastMs();
    rendered_ = true;
    cubeFresh_ = false;
}

const SpectralCube& View::cube() {
    if (!cubeFresh_) {
        if (!rendered_) render();
        pass_->readback(cube_);
        timings_.cube_ms = pass_->timings().readback_ms;
        cubeFresh_ = true;
    }
    return cube_;
}

ProbeReadout View::probe(int x, int y) {
    const SpectralCube& c = cube();
    return probePixel(*plan_, loaded_->representation, c, image_, x, y);
}

std::vector<std::pair<std::filesystem::path, std::string>> View::save(const std::filesystem::path& stem) {
    SpectralCube c = cube();
    const Representation& rep = loaded_->representation;
    projectCube(rep, c.data, c.bands());  // linear:K: as `metamer render` writes it
    Attributes provenance = renderProvenance(job_.scene.string(), "gpu", loaded_->scene.grid, rep);
    provenance.push_back({"metamer:preview", "saved from metamer preview"});
    OutputTargets targets;
    targets.cube = stem;
    targets.cube += ".exr";
    targets.png = stem;
    targets.png += ".png";
    RenderOutputs out(targets, c.width, c.height, loaded_->scene.grid, rep, plan_.get(), provenance);
    out.writeRows(0, c.height, c.data.data(), &image_);
    out.writeQuickLook(c, loaded_->library);  // only for a detector without a display path
    std::vector<std::pair<std::filesystem::path, std::string>> written;
    for (const WrittenFile& f : out.commit()) written.push_back({f.path, f.what});
    return written;
}

}  // namespace metamer::preview
