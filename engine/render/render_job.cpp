#include "render/render_job.h"

#include "core/cpu_count.h"
#include "core/memory_limits.h"
#include "core/statistics.h"
#include "core/timing.h"
#include "reference/cpu_renderer.h"
#include "interface.h"
#include "io/exr_file.h"
#include "render/display_frame.h"
#include "render/ground_truth.h"
#include "render/output_path.h"
#include "render/render_setup.h"
#include "render/strip_render.h"
#include "render/tonemap_pass.h"
#include "represent/representation.h"
#include "scene/scene_json.h"
#include "spectral/library.h"
#include "vk/context.h"

#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <memory>

namespace metamer {

const char* metamerVersion() { return METAMER_VERSION; }

namespace {
OutputFiles parseWrite(const std::vector<std::string>& names, const Where& where) {
    OutputFiles f{false, false, false, false, false};
    const std::vector<std::pair<std::string, bool*>> outputs = {
        {"cube", &f.cube},         {"png", &f.png},          {"xyz", &f.xyz},          {"responses", &f.responses},
        {"edges", &f.edges},       {"reflectance", &f.reflectance}, {"illumination", &f.illumination},
        {"ids", &f.ids},           {"depth", &f.depth},      {"normal", &f.normal}};
    std::vector<std::string> known;
    for (const auto& o : outputs) known.push_back(o.first);
    const std::string list = fmt::format("{}", fmt::join(known, ", "));
    if (names.empty()) failInput(where, "no output named; expected one or more of {}", list);
    for (const auto& n : names) {
        const auto found = std::find_if(outputs.begin(), outputs.end(), [&](const auto& o) { return o.first == n; });
        if (found != outputs.end()) {
            *found->second = true;
            continue;
        }
        std::string near = closestMatch(n, known);
        failInput(where, "'{}' is not an output; expected one of {}{}", n, list,
                  near.empty() ? "" : fmt::format(" (did you mean '{}'?)", near));
    }
    return f;
}

std::string gib(uint64_t bytes) { return fmt::format("{:.1f} GiB", double(bytes) / double(uint64_t(1) << 30)); }

}  // namespace

std::string RenderMemory::describe() const {
    std::string parts = "cube " + gib(cube);
    if (target) parts += ", GPU target " + gib(target);
    if (display) parts += ", display " + gib(display);
    return fmt::format("{} ({})", gib(total()), parts);
}

RenderMemory estimateRenderMemory(int width, int height, int bands, int ssaa, Backend backend, bool display,
                                  bool cube) {
    // 64-bit throughout: 16384² pixels × 4601 bands × 4 bytes is 4.9e12.
    const uint64_t pixels = uint64_t(std::max(width, 0)) * uint64_t(std::max(height, 0));
    const uint64_t s = uint64_t(std::max(ssaa, 1));
    const bool responsePass = backend == Backend::Gpu && !cube;
    const uint64_t channels = responsePass ? TONEMAP_MAX_CHANNELS : uint64_t(std::max(bands, 0));
    const uint64_t layers = (channels + 3) / 4;  // 4 bands (or channels) per RGBA32F layer
    RenderMemory m;
    m.cube = responsePass ? 0 : pixels * uint64_t(std::max(bands, 0)) * sizeof(float);
    if (backend == Backend::Gpu) {
        const uint64_t samples = pixels * s * s;
        const uint64_t targetBytes = samples * layers * 4 * sizeof(float);
        // The target, its readback copy (none for the response pass), the depth buffer.
        m.target = (responsePass ? 1 : 2) * targetBytes + samples * sizeof(float);
    }
    if (display) {
        // The display image: up to 8 float responses, 3 float XYZ, 3 uint16 counts, a clip byte.
        uint64_t perPixel = 8 * 4 + 3 * 4 + 3 * 2 + 1;
        // GPU: 4 RGBA32F attachments and a host buffer they are read back into.
        if (backend == Backend::Gpu) perPixel += 2 * 4 * 4 * sizeof(float);
        m.display = pixels * perPixel;
    }
    return m;
}

TonemapSettings tonemapSettings(const RenderJob& job, const Scene& scene, OutputFiles* files) {
    const OutputSettings& o = scene.output;
    Where sceneOut = o.where.file.empty() ? Where{scene.file.string(), "output"} : o.where;
    TonemapSettings s;
    if (job.detector) s.detector = *job.detector;
    else if (o.detector) s.detector = *o.detector;
    if (job.adaptation) s.adaptation = parseAdaptation(*job.adaptation, Where{"", "--adapt"});
    else if (o.adaptation) s.adaptation = parseAdaptation(*o.adaptation, sceneOut.child("adaptation"));
    if (job.display) s.display = *job.display;
    else if (o.display) s.display = *o.display;
    if (job.bits) s.bits = *job.bits;
    else if (o.bits) s.bits = *o.bits;
    if (job.integration) s.integration = parseIntegration(*job.integration, Where{"", "--integration"});
    else if (o.integration) s.integration = parseIntegration(*o.integration, sceneOut.child("integration"));
    std::string xyz = job.xyz ? *job.xyz : o.xyz ? *o.xyz : "relative";
    if (xyz != "relative" && xyz != "absolute")
        failInput(Where{"", "--xyz"}, "'{}' is not an XYZ scale; expected relative or absolute", xyz);
    s.absolute = xyz == "absolute";
    if (files) {
        if (job.write) *files = parseWrite(*job.write, Where{"", "--write"});
        else if (o.write) *files = parseWrite(*o.write, sceneOut.child("write"));
        else *files = OutputFiles{};
        if (job.writeCube) files->cube = true;
    }
    return s;
}

namespace {

// An edge is a pixel that, or a neighbour of which, sees something else — another opaque surface,
// or through another set of transparent ones: there rasterization and ray casting may pick
// different surfaces, so the golden comparisons skip it (255). A shadow
// boundary is a pixel that, or a neighbour of which, sees a different set of blocked lights, or
// whose sub-samples do (128): there the GPU's shadow map may put the boundary up to a texel away.
std::vector<uint16_t> edgeMask(const ReferenceImage& img) {
    const int W = img.cube.width, H = img.cube.height;
    std::vector<uint16_t> edges(size_t(W) * H, 0);
    const bool shadows = img.shadows.size() == edges.size();
    const bool crossings = img.crossings.size() == edges.size();
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const size_t at = size_t(y) * W + x;
            const int32_t id = img.objectId[at];
            const uint64_t blocked = shadows ? img.shadows[at] : 0;
            const uint32_t crossed = crossings ? img.crossings[at] : 0;
            bool edge = id == kMixedId || crossed == kMixedCrossings, boundary = blocked == kMixedShadows;
            for (int dy = -1; dy <= 1 && !edge; ++dy)
                for (int dx = -1; dx <= 1 && !edge; ++dx) {
                    int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= W || ny >= H) continue;
                    const size_t there = size_t(ny) * W + nx;
                    edge = img.objectId[there] != id || (crossings && img.crossings[there] != crossed);
                    boundary = boundary || (shadows && img.shadows[there] != blocked);
                }
            edges[at] = edge ? 255 : boundary ? 128 : 0;
        }
    return edges;
}

// What the render needs at once, checked against the hard limits before anything that grows with
// the image is allocated. The GPU path renders in strips when memory is short, so for it only the
// files' size is a limit; the CPU reference holds the whole image.
void refuseAbsurdSizes(const RenderJob& job, const Scene& scene, const Grid& grid, const RenderMemory& memory) {
    const bool cpu = job.backend == Backend::Cpu;
    if (cpu ? memory.total() <= kMaxRenderMemory : memory.cube <= kMaxStreamedCube) return;
    failInput(Where{scene.file.string(), "camera"},
              "a {}×{} render on {} bands{} would need about {}, more than the {} a render may {}; "
              "reduce camera.width and camera.height or use a coarser grid",
              scene.camera.width, scene.camera.height, grid.bands(),
              !cpu && job.ssaa > 1 ? fmt::format(" with ssaa {}", job.ssaa) : "", memory.describe(),
              gib(cpu ? kMaxRenderMemory : kMaxStreamedCube), cpu ? "use" : "write as a cube");
}

// The supersampled target must fit the device's framebuffer; say so with the scene's key (the
// pass would refuse it too, but without naming the file).
void refuseOversizedTarget(const RenderJob& job, const Scene& scene, const vk::Context& ctx) {
    const VkPhysicalDeviceLimits& lim = ctx.properties().limits;
    uint64_t tw = uint64_t(scene.camera.width) * job.ssaa, th = uint64_t(scene.camera.height) * job.ssaa;
    uint64_t maxW = std::min(lim.maxFramebufferWidth, lim.maxImageDimension2D);
    uint64_t maxH = std::min(lim.maxFramebufferHeight, lim.maxImageDimension2D);
    if (tw > maxW || th > maxH)
        failInput(Where{scene.file.string(), "camera"},
                  "a {}×{} render with ssaa {} needs a {}×{} target, beyond this device's largest framebuffer "
                  "{}×{}; reduce camera.width and camera.height or --ssaa",
                  scene.camera.width, scene.camera.height, job.ssaa, tw, th, maxW, maxH);
}

// The job's Vulkan context: the caller's (metamer batch: one device for many jobs), or one of its
// own. finish() says how many validation errors the job caused; an own context is destroyed first,
// since leak reports arrive at device destruction.
class JobContext {
public:
    explicit JobContext(const RenderJob& job)
        : own_(job.context ? nullptr : std::make_unique<vk::Context>(jobContextOptions(job))),
          ctx_(job.context ? job.context : own_.get()),
          before_(job.context ? job.context->validationErrors() : 0) {}
    vk::Context& operator*() { return *ctx_; }
    vk::Context* operator->() { return ctx_; }
    vk::Context* get() { return ctx_; }
    uint32_t finish() {
        if (own_) {
            own_.reset();
            return vk::Context::validationErrorsAtExit();
        }
        return ctx_->validationErrors() - before_;
    }

private:
    std::unique_ptr<vk::Context> own_;
    vk::Context* ctx_;
    uint32_t before_;
};

// The whole-image arrays a render held in memory keeps (RenderJob::capture; the sizes
// RenderOutputs::captureInto allocates), in bytes.
uint64_t capturedBytes(int width, int height, const OutputFiles& files, const Representation& representation,
                       const TonemapPlan* plan) {
    const uint64_t pixels = uint64_t(width) * uint64_t(height);
    const bool colorimetric = plan && plan->mode != TonemapMode::ResponsesOnly;
    uint64_t perPixel = 0;
    if (files.cube) perPixel += uint64_t(representation.channels()) * sizeof(float);
    if (files.png && colorimetric) perPixel += 3 * sizeof(uint16_t);
    if (files.xyz && colorimetric) perPixel += 3 * sizeof(float);
    if (files.responses && plan) perPixel += plan->detector.channels.size() * sizeof(float);
    if (files.edges) perPixel += sizeof(uint16_t);
    const uint64_t bands = uint64_t(representation.grid.bands());
    if (files.reflectance) perPixel += bands * sizeof(float);
    if (files.illumination) perPixel += bands * sizeof(float);
    if (files.ids) perPixel += 2 * sizeof(int32_t);
    if (files.depth) perPixel += sizeof(float);
    if (files.normal) perPixel += 3 * sizeof(float);
    if (files.groundTruth()) perPixel += 1;
    return pixels * perPixel;
}

// A render held in memory cannot stream its arrays to files: they stay whole for as long as the
// caller keeps them, so they count against the memory budget first, and the render gets what is
// left (in strips on the GPU, which need at least two 16-row strips' worth). Refused before
// anything is allocated when that does not fit, with the estimate — rather than a bare
// MemoryError, or growing past the budget.
void refuseCaptureOverBudget(const RenderJob& job, const Scene& scene, const Grid& grid, uint64_t budget,
                             uint64_t held, const RenderMemory& memory, const RenderMemory& perRow, bool strippable) {
    const uint64_t rows = std::min<uint64_t>(16, uint64_t(std::max(scene.camera.height, 1)));
    const uint64_t rendering = strippable ? std::min(memory.total(), 2 * rows * perRow.total()) : memory.total();
    if (held + rendering <= budget) return;
    failInput(Where{scene.file.string(), "camera"},
              "a {}×{} render on {} bands{} kept in memory would need about {} ({} for the arrays kept, {} to render "
              "them), over the memory budget of {}; reduce camera.width and camera.height, use a coarser grid, keep "
              "fewer outputs (write) or raise memory_budget (MiB; default a quarter of the machine's memory)",
              scene.camera.width, scene.camera.height, grid.bands(),
              job.ssaa > 1 ? fmt::format(" with ssaa {}", job.ssaa) : "", memorySize(held + rendering),
              memorySize(held), memorySize(rendering), memorySize(budget));
}

// Strip rows when the render is over the memory budget (GPU), or, with a progress hook, larger
// than job.stripPixels samples (when strips can make its outputs), else 0; the reason for strips
// over the budget in `why` (none for the hook's: they are not the user's concern).
int stripRowsFor(const RenderJob& job, const Scene& scene, uint64_t budget, const RenderMemory& memory,
                 const RenderMemory& perRow, bool quickLookOrEdges, std::string& why) {
    // Samples, not pixels: with ssaa each pixel is ssaa² of them.
    const int H = scene.camera.height;
    const uint64_t samplesPerRow = uint64_t(scene.camera.width) * uint64_t(job.ssaa) * uint64_t(job.ssaa);
    int interruptRows = 0;
    if (job.progress && job.stripPixels > 0 && job.backend == Backend::Gpu && !quickLookOrEdges && job.frames <= 1 &&
        samplesPerRow * uint64_t(H) > job.stripPixels)
        interruptRows = std::max(16, int(std::min<uint64_t>(job.stripPixels / samplesPerRow, uint64_t(H))) / 16 * 16);
    if (memory.total() <= budget) return interruptRows > 0 && interruptRows < H ? interruptRows : 0;
    auto mib = [](uint64_t b) { return double(b) / (1 << 20); };
    why = fmt::format("the render needs about {:.0f} MiB at once, over the budget of {:.0f} MiB", mib(memory.total()),
                      mib(budget));
    if (job.backend != Backend::Gpu)
        failInput(Where{"", "--memory-budget"}, "{}; the CPU reference renders whole images (use the GPU backend, "
                  "which renders in strips, or raise --memory-budget)", why);
    if (quickLookOrEdges || job.frames > 1)
        failInput(Where{"", "--memory-budget"}, "{}; strips cannot make the edges mask, a quick look, the "
                  "ground truth (reflectance, illumination, ids, depth, normal) or repeated frames", why);
    // Half the budget per strip (the rest for the writers and the process), in whole 16-row EXR
    // blocks when there is room; no taller than the hook's strips.
    int rows = int(std::max<uint64_t>(1, budget / 2 / std::max<uint64_t>(1, perRow.total())));
    if (rows >= 16) rows -= rows % 16;
    return interruptRows > 0 ? std::min(rows, interruptRows) : rows;
}

// The ground truth `files` asks for, made by the job's backend and written to `out`
// (render/ground_truth.h); nothing without.
void writeGroundTruth(const RenderJob& job, const LoadedScene& loaded, const OutputFiles& files, vk::Context* ctx,
                      RenderOutputs& out, RenderJobResult& r) {
    if (!files.groundTruth()) return;
    GroundTruthJob g;
    g.scene = &loaded.scene;
    g.spectra = &loaded.spectra;
    g.backend = job.backend;
    g.ssaa = job.ssaa;
    g.readback = job.readback;
    g.context = ctx;
    const GroundTruth truth = renderGroundTruth(g, files);
    const auto t = Clock::now();
    out.writeGroundTruth(truth.images());
    r.timings.ground_truth_ms = truth.ms;
    r.timings.write_ms += msSince(t);
}

// The job's progress hook with the time since the job started (render/render_progress.h); a no-op
// without a hook.
using ProgressReport = std::function<void(const char* unit, int done, int total)>;

// The image strip by strip on the GPU into `out` (render/strip_render); returns the strip count.
int renderStripsInto(const RenderJob& job, LoadedScene& loaded, const TonemapPlan* plan, int rows, RenderOutputs& out,
                     RenderJobResult& r, const ProgressReport& report) {
    JobContext ctx(job);
    StripJob sj;
    sj.scene = &loaded.scene;
    sj.rendered = &loaded.rendered;
    sj.representation = &loaded.representation;
    sj.plan = plan;
    sj.context = ctx.get();
    sj.stripRows = rows;
    sj.ssaa = job.ssaa;
    sj.readback = job.readback;
    sj.outputs = &out;
    sj.afterStrip = [&](int done, int total) { report("strip", done, total); };
    const StripResult sr = renderInStrips(sj);
    r.validationErrors = ctx.finish();
    r.timings.shading_ms = sr.shading_ms;
    r.timings.tonemap_ms = sr.tonemap_ms;
    r.timings.readback_ms = sr.readback_ms;
    r.backendDescription = sr.description;
    r.responsePass = sr.responsePass;
    r.displayOnly = sr.displayOnly;
    r.clippedPixels = sr.clippedPixels;
    return sr.strips;
}

// Display outputs only, on the GPU into `out`: the response pass and the tonemap pass
// (render/display_frame.h), one or more whole frames; the bands are never drawn.
void renderDisplayFrames(const RenderJob& job, LoadedScene& loaded, const TonemapPlan& plan, const OutputFiles& files,
                         RenderOutputs& out, RenderJobResult& r, const ProgressReport& report) {
    JobContext ctx(job);
    {
        refuseOversizedTarget(job, loaded.scene, *ctx);
        SpectralPassOptions po;
        po.ssaa = job.ssaa;
        DisplayFrame frame(*ctx, loaded.scene, loaded.rendered, plan, po, out.displayOutputs());
        DisplayImage image;
        std::vector<double> shading, tonemap;
        const int frames = std::max(1, job.frames);
        report("frame", 0, frames);
        for (int f = 0; f < frames; ++f) {
            image = frame.render();
            shading.push_back(frame.timings().shading_ms);
            tonemap.push_back(frame.timings().tonemap_ms);
            report("frame", f + 1, frames);
        }
        r.responsePass = frame.passPlan().responses;
        r.displayOnly = true;
        r.timings.upload_ms = frame.timings().upload_ms;
        r.timings.shadow_ms = frame.timings().shadow_ms;
        r.timings.shading_ms = shading[0];
        r.timings.tonemap_ms = tonemap[0];
        r.timings.frames = int(shading.size());
        r.timings.first_shading_ms = shading[0];
        if (shading.size() > 1) {
            r.timings.median_shading_ms = median({shading.begin() + 1, shading.end()});
            r.timings.median_tonemap_ms = median({tonemap.begin() + 1, tonemap.end()});
        }
        r.backendDescription = ctx->deviceInfo().name + ": " + frame.passPlan().describe();
        r.clippedPixels = image.clippedPixels;
        auto t = Clock::now();
        out.writeRows(0, loaded.scene.camera.height, nullptr, &image);
        if (out.needsQuickLook()) {
            // A custom detector's quick look: the CIE 1931 observer's responses (radiometric XYZ,
            // riemann, as color/quick_look integrates the cube) from a response pass of their own.
            const TonemapPlan cie1931 =
                makeScenePlan(TonemapSettings{}, loaded.scene, loaded.spectra, loaded.library, &loaded.representation);
            DisplayFrame look(*ctx, loaded.scene, loaded.rendered, cie1931, po, TonemapOutputs{false, false, true});
            out.writeQuickLookFromXyz(look.render().responses);
        }
        r.timings.write_ms = msSince(t);
        writeGroundTruth(job, loaded, files, ctx.get(), out, r);
    }
    r.validationErrors = ctx.finish();
}

// One or more whole frames on the GPU into `out`: the bands, and the display path over them.
void renderGpuFrames(const RenderJob& job, LoadedScene& loaded, const TonemapPlan* plan, const OutputFiles& files,
                     RenderOutputs& out, RenderJobResult& r, const ProgressReport& report) {
    JobContext ctx(job);
    {
        refuseOversizedTarget(job, loaded.scene, *ctx);
        SpectralPassOptions po;
        po.ssaa = job.ssaa;
        po.readback = job.readback;
        po.sampled = plan != nullptr;
        SpectralPass pass(*ctx, loaded.scene, loaded.rendered, po);
        std::unique_ptr<TonemapPass> tonemap;
        if (plan) tonemap = std::make_unique<TonemapPass>(*ctx, pass, *plan);
        SpectralCube cube;
        DisplayImage image;
        std::vector<double> shading, readback, tonemapMs;
        // Progress per declared pass (depth pre-pass, band passes, ...) of every frame: with a hook
        // the passes are submitted one at a time, so a long frame reports and can stop between them.
        const int frames = std::max(1, job.frames), passes = pass.framePasses();
        report("pass", 0, frames * passes);
        for (int f = 0; f < frames; ++f) {
            std::function<void(int, int)> afterPass;
            if (job.progress)
                afterPass = [&, f](int done, int) { report("pass", f * passes + done, frames * passes); };
            pass.draw(afterPass);
            shading.push_back(pass.timings().shading_ms);
            if (tonemap) image = tonemap->render();
            tonemapMs.push_back(tonemap ? tonemap->lastMs() : 0.0);
            if (out.needsCube()) {
                pass.readback(cube);
                readback.push_back(pass.timings().readback_ms);
            } else {
                readback.push_back(0.0);
            }
        }
        r.timings.upload_ms = pass.timings().upload_ms;
        r.timings.shadow_ms = pass.timings().shadow_ms;
        r.timings.shading_ms = shading[0];
        r.timings.readback_ms = readback[0];
        r.timings.tonemap_ms = tonemap ? tonemap->lastMs() : 0.0;
        r.timings.frames = int(shading.size());
        r.timings.first_shading_ms = shading[0];
        if (shading.size() > 1) {
            r.timings.median_shading_ms = median({shading.begin() + 1, shading.end()});
            r.timings.median_readback_ms = median({readback.begin() + 1, readback.end()});
            r.timings.median_tonemap_ms = median({tonemapMs.begin() + 1, tonemapMs.end()});
        }
        r.backendDescription = ctx->deviceInfo().name + ": " + pass.plan().describe();
        r.clippedPixels = image.clippedPixels;
        auto t = Clock::now();
        // linear:K: the pixels are the projections onto the basis (Peercy's result).
        if (!cube.data.empty()) projectCube(loaded.representation, cube.data, cube.bands());
        out.writeRows(0, loaded.scene.camera.height, cube.data.empty() ? nullptr : cube.data.data(),
                      tonemap ? &image : nullptr);
        out.writeQuickLook(cube, loaded.library);
        r.timings.write_ms = msSince(t);
        writeGroundTruth(job, loaded, files, ctx.get(), out, r);
    }
    r.validationErrors = ctx.finish();
}

// The CPU reference (double precision) and its tonemap into `out`.
void renderReferenceFrame(const RenderJob& job, LoadedScene& loaded, const TonemapPlan* plan, const OutputFiles& files,
                          RenderOutputs& out, RenderJobResult& r, const ProgressReport& report) {
    auto t = Clock::now();
    ReferenceOptions ro;
    ro.ssaa = job.ssaa;
    const int rows = loaded.scene.camera.height;
    report("row", 0, rows);
    ro.progress = [&](int done, int total) { report("row", done, total); };
    ReferenceImage img = renderReference(loaded.scene, loaded.rendered, ro);
    report("row", rows, rows);
    r.timings.shading_ms = msSince(t);
    DisplayImage image;
    if (plan) {
        t = Clock::now();
        image = tonemapReference(*plan, img.cube);
        r.timings.tonemap_ms = msSince(t);
    }
    r.backendDescription = fmt::format("CPU reference (double precision ray casting), {} channels, ssaa {}",
                                       loaded.rendered.grid.bands(), job.ssaa);
    r.clippedPixels = image.clippedPixels;
    t = Clock::now();
    projectCube(loaded.representation, img.cube.data, img.cube.bands());
    out.writeRows(0, img.cube.height, img.cube.data.data(), plan ? &image : nullptr);
    out.writeQuickLook(img.cube, loaded.library);
    out.writeEdges(edgeMask(img));
    r.timings.write_ms = msSince(t);
    writeGroundTruth(job, loaded, files, nullptr, out, r);
}

}  // namespace

RenderJobResult runRenderJob(const RenderJob& job) {
    RenderJobResult r;
    const auto start = Clock::now();
    r.threads = usableCpuCount();
    r.threadsSource = cpuCount().source;
    const ProgressReport report = [&](const char* unit, int done, int total) {
        if (job.progress) job.progress(RenderProgress{unit, done, total, msSince(start) / 1000.0});
    };

    // 1. The scene with the job's overrides and grid, on the grid, in the job's representation,
    //    and the display plan when an output needs one.
    const std::string stem = job.outStem.empty() ? job.scene.stem().string() : job.outStem;
    requireOutputStem(stem, job.outStem.empty() ? Where{job.scene.string()} : Where{"", "--out"});
    auto t = Clock::now();
    std::unique_ptr<LoadedScene> loaded = loadJobScene(job);
    const Scene& scene = loaded->scene;
    OutputFiles files;
    const TonemapSettings settings = tonemapSettings(job, scene, &files);
    const bool display = files.png || files.xyz || files.responses;
    // Checked before anything is rendered: the writers would find it only at the end.
    if (!knownExrCompression(job.compression))
        failInput(Where{"", "--compression"}, "'{}' is not an OpenEXR compression; expected one of {} (zip and zips "
                  "take a level :1 to :9, dwaa and dwab a :level)", job.compression, exrCompressionNames());
    if (files.edges && job.backend != Backend::Cpu)
        failInput(Where{"", "--write"}, "the edges mask comes from the CPU reference's object ids; use --backend cpu");

    // 2. Refuse absurd sizes before anything that grows with the image is allocated.
    const int W = scene.camera.width, H = scene.camera.height, channels = loaded->rendered.grid.bands();
    std::optional<TonemapPlan> plan;
    if (display) {
        plan = makeJobTonemapPlan(job, *loaded, settings);
        r.displayDescription = plan->description;
        r.xyzUnits = plan->xyzUnits;
        if (plan->camera) r.cameraFitRmsDeltaE = plan->camera->rmsDeltaE2000;
    }
    const TonemapPlan* planPtr = plan ? &*plan : nullptr;
    // Whether the render holds the bands: for the cube or the mode's channel image; else the
    // display path draws the detector's channels only (render/display_frame.h), and a custom
    // detector's quick look the CIE 1931 observer's.
    const bool quickLook = files.png && planPtr && planPtr->mode == TonemapMode::ResponsesOnly;
    const bool needsBands = files.cube || files.edges || !display || job.backend == Backend::Cpu;
    // A scene whose display image needs the bands (two slabs, interreflection, emitters:
    // Scene::displayNeedsBands) draws them for the display image too (display_frame.cpp): its
    // memory is counted as the cube path's (the cube itself is not held, so this errs high).
    const bool drawsBands = needsBands || scene.displayNeedsBands();
    RenderMemory memory =
        estimateRenderMemory(W, H, loaded->grid.bands(), job.ssaa, job.backend, display, drawsBands);
    // The spectral ground truth: a cube each, held whole (and a target of the cube's size to draw it).
    const uint64_t truthCubes = uint64_t(files.reflectance) + uint64_t(files.illumination);
    memory.cube += truthCubes * uint64_t(W) * uint64_t(H) * uint64_t(loaded->grid.bands()) * sizeof(float);
    const RenderMemory perRow = estimateRenderMemory(W, 1, channels, job.ssaa, job.backend, display, drawsBands);
    uint64_t budget = job.memoryBudget ? job.memoryBudget : defaultMemoryBudget();
    uint64_t held = 0;
    if (job.capture) {
        held = capturedBytes(W, H, files, loaded->representation, planPtr);
        refuseCaptureOverBudget(job, scene, loaded->grid, budget, held, memory, perRow,
                                job.backend == Backend::Gpu && !files.edges && !quickLook && job.frames == 1);
        budget -= held;
    }
    refuseAbsurdSizes(job, scene, loaded->grid, memory);
    r.timings.load_ms = msSince(t);
    r.grid = loaded->grid;
    r.width = W;
    r.height = H;

    // 3. Every output opened at once (temporary files), whatever renders the pixels.
    std::string why;
    // Whole images only: the edges mask, a quick look and the ground truth (no strips for a hook either).
    const int stripRows = stripRowsFor(job, scene, budget, memory, perRow,
                                       files.edges || quickLook || files.groundTruth(), why);
    OutputOptions oo;
    oo.half = job.half;
    oo.compression = job.compression;
    Attributes provenance = renderProvenance(job.scene.string(), job.backend == Backend::Gpu ? "gpu" : "cpu",
                                             loaded->grid, loaded->representation);
    // What else a file needs to be remade: the overrides, the display path, the software.
    if (!job.overrides.empty()) provenance.push_back({"metamer:overrides", fmt::format("{}", fmt::join(job.overrides, " "))});
    if (planPtr) provenance.push_back({"metamer:display", planPtr->description});
    provenance.push_back({"metamer:version", metamerVersion()});
    {
        const Where sceneOut = scene.output.where.file.empty() ? Where{scene.file.string(), "output"} : scene.output.where;
        if (job.format) oo.formats = parseCubeFormats(*job.format, Where{"", "--format"});
        else if (scene.output.format) oo.formats = parseCubeFormats(*scene.output.format, sceneOut.child("format"));
        else if (const CubeContainer* named = namedCubeFormat(job.outExtension)) oo.formats = {{named, ""}};
        if (!job.outExtension.empty())
            requireNamedOutput((job.outDir / (stem + job.outExtension)).lexically_normal(), files.cube,
                               files.png && planPtr, oo.formats,
                               job.format ? "--format" : scene.output.format ? "the scene's output.format" : "");
        const bool onlyExr = oo.formats.size() == 1 && oo.formats.front().format->name == "exr";
        if (!onlyExr && !loaded->representation.mode.spectral())
            failInput(job.format ? Where{"", "--format"} : sceneOut.child("format"),
                      "HDF5 and ENVI hold spectral cubes; the {} mode's channel image is written as OpenEXR only",
                      loaded->representation.mode.name());
    }
    // Options that change only a file this run does not write: said, since the user expected them
    // to matter (the run goes on: a sweep may set them for jobs that write other things).
    {
        const bool exrNamed = std::any_of(oo.formats.begin(), oo.formats.end(),
                                          [](const ChosenCubeFormat& f) { return f.format->name == "exr"; });
        const bool exrCube = files.cube && (exrNamed || !loaded->representation.mode.spectral());
        if (job.half && !(exrCube && loaded->representation.mode.spectral()))
            warn(Where{"", "--half"}, "has no effect: float16 applies to the OpenEXR spectral cube, which this run "
                 "does not write");
        if (job.compression != "piz" && !exrCube)
            warn(Where{"", "--compression"}, fmt::format("'{}' has no effect: it applies to the OpenEXR cube, which "
                 "this run does not write", job.compression));
        if (job.bits && !files.png)
            warn(Where{"", "--bits"}, fmt::format("{} has no effect: it sets the display PNG's counts, which this run "
                 "does not write", *job.bits));
    }
    RenderOutputs out(job.capture ? OutputTargets{}
                                  : renderTargets(job.outDir, stem, files, loaded->representation, planPtr, oo.formats),
                      W, H, loaded->grid, loaded->representation, planPtr, provenance, oo);
    if (job.capture) {
        job.capture->outputs.keep = files;
        out.captureInto(&job.capture->outputs);
    }

    // 4. The pixels: strips over the memory budget, whole GPU frames, or the CPU reference.
    int strips = 1;
    if (stripRows > 0) {
        strips = renderStripsInto(job, *loaded, planPtr, stripRows, out, r, report);
        if (!why.empty())
            r.notes.push_back(job.capture ? why + fmt::format(" (what is left after {} for the arrays kept); rendered "
                                                              "in {} strips of {} rows into the arrays",
                                                              memorySize(held), strips, stripRows)
                                          : why + fmt::format("; rendered in {} strips of {} rows and streamed to the "
                                                              "files", strips, stripRows));
    } else if (job.backend == Backend::Gpu && !out.needsCube() && planPtr) {
        renderDisplayFrames(job, *loaded, *planPtr, files, out, r, report);
    } else if (job.backend == Backend::Gpu) {
        renderGpuFrames(job, *loaded, planPtr, files, out, r, report);
    } else {
        renderReferenceFrame(job, *loaded, planPtr, files, out, r, report);
    }

    // 5. Every file renamed into place.
    t = Clock::now();
    r.written = out.commit(strips, stripRows, job.beforeCommit);
    r.clampedToHalf = out.clampedToHalf();
    if (files.xyz && planPtr && planPtr->mode == TonemapMode::ResponsesOnly)
        r.notes.push_back(fmt::format("no XYZ output: detector {} has no colorimetric path", planPtr->detector.name));
    r.timings.write_ms += msSince(t);
    if (job.capture) {
        CapturedRender& c = *job.capture;
        c.grid = loaded->grid;
        c.stem = stem;
        c.plan = plan;  // a copy: `out` still points at this one
        c.provenance = provenance;
        c.options = oo;
        c.loaded = std::move(loaded);
    }
    r.timings.total_ms = msSince(start);
    return r;
}

std::vector<WrittenFile> saveCapturedRender(const CapturedRender& render, const std::filesystem::path& dir) {
    const CapturedOutputs& c = render.outputs;
    if (!render.loaded) failRuntime("this render holds nothing to save");
    const TonemapPlan* plan = render.plan ? &*render.plan : nullptr;
    // What was kept: the render's `write` as far as it could be made (captureInto), so a custom
    // detector's quick-look PNG is not among them.
    const OutputFiles files = c.keep;
    const Representation& representation = render.loaded->representation;
    RenderOutputs out(renderTargets(dir, render.stem, files, representation, plan, render.options.formats), c.width,
                      c.height, render.grid,
                      representation, plan, render.provenance, render.options);
    DisplayImage image;
    image.width = c.width;
    image.height = c.height;
    image.channels = int(c.responseChannels);
    image.counts = c.counts;
    image.xyz = c.xyz;
    image.responses = c.responses;
    out.writeRows(0, c.height, c.cube.empty() ? nullptr : c.cube.data(), plan ? &image : nullptr);
    if (!c.edges.empty()) out.writeEdges(c.edges);
    if (out.needsGroundTruth()) {
        GroundTruthImages truth;
        truth.reflectance = c.reflectance.empty() ? nullptr : c.reflectance.data();
        truth.illumination = c.illumination.empty() ? nullptr : c.illumination.data();
        truth.geometry = c.geometry.mask.empty() ? nullptr : &c.geometry;
        truth.legend = c.legend;
        out.writeGroundTruth(truth);
    }
    return out.commit();
}

}  // namespace metamer
