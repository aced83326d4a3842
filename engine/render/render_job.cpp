#include "render/render_job.h"

#include "io/image_file.h"
#include "io/quicklook_png.h"
#include "io/spectral_exr.h"
#include "reference/cpu_renderer.h"
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
#include <memory>

namespace metamer {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}
double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

OutputFiles parseWrite(const std::vector<std::string>& names, const Where& where) {
    OutputFiles f{false, false, false, false, false};
    for (const auto& n : names) {
        if (n == "cube") f.cube = true;
        else if (n == "png") f.png = true;
        else if (n == "xyz") f.xyz = true;
        else if (n == "responses") f.responses = true;
        else if (n == "edges") f.edges = true;
        else {
            std::string near = closestMatch(n, {"cube", "png", "xyz", "responses", "edges"});
            failInput(where, "'{}' is not an output; expected cube, png, xyz, responses or edges{}", n,
                      near.empty() ? "" : fmt::format(" (did you mean '{}'?)", near));
        }
    }
    return f;
}

// A file name part for a detector: "camera:nikon_d5100" → "camera-nikon_d5100".
std::string detectorFileName(const std::string& name) {
    std::string s = name.rfind("csv:", 0) == 0 ? "csv-" + std::filesystem::path(name.substr(4)).stem().string() : name;
    std::replace(s.begin(), s.end(), ':', '-');
    return s;
}

std::string gib(uint64_t bytes) { return fmt::format("{:.1f} GiB", double(bytes) / double(uint64_t(1) << 30)); }

}  // namespace

std::string RenderMemory::describe() const {
    std::string parts = "cube " + gib(cube);
    if (target) parts += ", GPU target " + gib(target);
    if (display) parts += ", display " + gib(display);
    return fmt::format("{} ({})", gib(total()), parts);
}

RenderMemory estimateRenderMemory(int width, int height, int bands, int ssaa, Backend backend, bool display) {
    // 64-bit throughout: 16384² pixels × 4601 bands × 4 bytes is 4.9e12.
    const uint64_t pixels = uint64_t(std::max(width, 0)) * uint64_t(std::max(height, 0));
    const uint64_t s = uint64_t(std::max(ssaa, 1));
    const uint64_t layers = (uint64_t(std::max(bands, 0)) + 3) / 4;  // 4 bands per RGBA32F layer
    RenderMemory m;
    m.cube = pixels * uint64_t(std::max(bands, 0)) * sizeof(float);
    if (backend == Backend::Gpu) {
        const uint64_t samples = pixels * s * s;
        const uint64_t targetBytes = samples * layers * 4 * sizeof(float);
        m.target = 2 * targetBytes + samples * sizeof(float);  // target, readback copy, depth
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
    }
    return s;
}

RenderJobResult runRenderJob(const RenderJob& job) {
    RenderJobResult r;
    auto start = Clock::now();

    auto t = Clock::now();
    // The scene with the job's overrides and grid, on the grid, in the job's representation.
    std::unique_ptr<LoadedScene> loaded = loadJobScene(job);
    SpectrumLibrary& library = loaded->library;
    Scene& scene = loaded->scene;
    Representation& representation = loaded->representation;
    // What the renderers see: the spectra in the mode's channels (the same spectra in full mode).
    SceneOnGrid& rendered = loaded->rendered;
    OutputFiles files;
    TonemapSettings settings = tonemapSettings(job, scene, &files);
    bool display = files.png || files.xyz || files.responses;
    // Refuse absurd sizes here, before anything that grows with the image is allocated.
    RenderMemory memory =
        estimateRenderMemory(scene.camera.width, scene.camera.height, scene.grid.bands(), job.ssaa, job.backend, display);
    // The GPU path renders in strips when memory is short (below), so for it only the files' size
    // is a limit; the CPU reference holds the whole image.
    bool tooLarge = job.backend == Backend::Cpu ? memory.total() > kMaxRenderMemory : memory.cube > kMaxStreamedCube;
    if (tooLarge)
        failInput(Where{scene.file.string(), "camera"},
                  "a {}×{} render on {} bands{} would need about {}, more than the {} a render may {}; "
                  "reduce camera.width and camera.height or use a coarser grid",
                  scene.camera.width, scene.camera.height, scene.grid.bands(),
                  job.backend == Backend::Gpu && job.ssaa > 1 ? fmt::format(" with ssaa {}", job.ssaa) : "",
                  memory.describe(), gib(job.backend == Backend::Cpu ? kMaxRenderMemory : kMaxStreamedCube),
                  job.backend == Backend::Cpu ? "use" : "write as a cube");
    std::optional<TonemapPlan> plan;
    if (display) {
        plan = makeJobTonemapPlan(job, *loaded, settings);
        r.displayDescription = plan->description;
        r.xyzUnits = plan->xyzUnits;
        if (plan->camera) r.cameraFitRmsDeltaE = plan->camera->rmsDeltaE2000;
    }
    r.timings.load_ms = msSince(t);
    r.grid = scene.grid;
    r.width = scene.camera.width;
    r.height = scene.camera.height;
    bool responsesOnly = plan && plan->mode == TonemapMode::ResponsesOnly;
    // A custom detector has no display path: its PNG is the CIE 1931 quick look of the cube.
    bool needCube = files.cube || (files.png && responsesOnly) || job.backend == Backend::Cpu;

    if (files.edges && job.backend != Backend::Cpu)
        failInput(Where{"", "--write"}, "the edges mask comes from the CPU reference's object ids; use --backend cpu");

    // Larger than the memory budget: render in strips and stream every output (GPU backend).
    size_t perRow = bytesPerRow(scene.camera.width, rendered.grid.bands(), job.ssaa, display,
                                plan ? int(plan->detector.channels.size()) : 0);
    size_t budget = job.memoryBudget ? job.memoryBudget : defaultMemoryBudget();
    size_t needed = perRow * size_t(scene.camera.height);
    if (needed > budget) {
        auto mib = [](size_t b) { return double(b) / (1 << 20); };
        std::string why = fmt::format("the render needs about {:.0f} MiB at once, over the budget of {:.0f} MiB",
                                      mib(needed), mib(budget));
        if (job.backend != Backend::Gpu)
            failInput(Where{"", "--memory-budget"}, "{}; the CPU reference renders whole images (use the GPU backend, "
                      "which renders in strips, or raise --memory-budget)", why);
        if (files.edges || (files.png && responsesOnly) || job.frames > 1)
            failInput(Where{"", "--memory-budget"}, "{}; strips cannot make the edges mask, a quick look or "
                      "repeated frames", why);
        // Half the budget per strip (the rest for the writers and the process), in whole 16-row EXR
        // blocks when there is room.
        int rows = int(std::max<size_t>(1, budget / 2 / perRow));
        if (rows >= 16) rows -= rows % 16;
        auto ctx = std::make_unique<vk::Context>(jobContextOptions(job));
        std::string stem = job.scene.stem().string();
        StripJob sj;
        sj.scene = &scene;
        sj.rendered = &rendered;
        sj.representation = &representation;
        sj.plan = plan ? &*plan : nullptr;
        sj.context = ctx.get();
        sj.stripRows = rows;
        sj.ssaa = job.ssaa;
        sj.readback = job.readback;
        sj.half = job.half;
        sj.compression = job.compression;
        sj.provenance = {{"metamer:scene", job.scene.string()}, {"metamer:backend", "gpu"},
                         {"metamer:grid", scene.grid.str()}, {"metamer:resampling", resamplingName(scene.grid.resampling)},
                         {"metamer:mode", representation.mode.name()}};
        std::string tag = representation.mode.name();
        std::replace(tag.begin(), tag.end(), ':', '-');
        if (files.cube) sj.cube = job.outDir / (stem + (representation.mode.spectral() ? "" : "." + tag) + ".exr");
        if (files.png) sj.png = job.outDir / (stem + ".png");
        if (files.xyz && !responsesOnly) sj.xyz = job.outDir / (stem + ".xyz.exr");
        if (files.responses) sj.responses = job.outDir / (stem + "." + detectorFileName(plan->detector.name) + ".exr");
        t = Clock::now();
        StripResult sr = renderInStrips(sj);
        ctx.reset();
        r.validationErrors = vk::Context::validationErrorsAtExit();
        r.timings.shading_ms = sr.shading_ms;
        r.timings.tonemap_ms = sr.tonemap_ms;
        r.timings.readback_ms = sr.readback_ms;
        r.timings.total_ms = msSince(start);
        r.backendDescription = sr.description;
        r.clampedToHalf = sr.clampedToHalf;
        r.clippedPixels = sr.clippedPixels;
        for (const auto& p : {sj.cube, sj.png, sj.xyz, sj.responses})
            if (!p.empty()) r.written.push_back({p, fmt::format("written in {} strips of {} rows", sr.strips, rows)});
        r.notes.push_back(why + fmt::format("; rendered in {} strips of {} rows and streamed to the files", sr.strips,
                                            rows));
        return r;
    }

    SpectralCube cube;
    DisplayImage image;
    std::vector<uint16_t> edges;
    if (job.backend == Backend::Gpu) {
        auto ctx = std::make_unique<vk::Context>(jobContextOptions(job));
        {
            // The supersampled target must fit the device's framebuffer; say so with the scene's key
            // (the pass would refuse it too, but without naming the file).
            const VkPhysicalDeviceLimits& lim = ctx->properties().limits;
            uint64_t tw = uint64_t(scene.camera.width) * job.ssaa, th = uint64_t(scene.camera.height) * job.ssaa;
            uint64_t maxW = std::min(lim.maxFramebufferWidth, lim.maxImageDimension2D);
            uint64_t maxH = std::min(lim.maxFramebufferHeight, lim.maxImageDimension2D);
            if (tw > maxW || th > maxH)
                failInput(Where{scene.file.string(), "camera"},
                          "a {}×{} render with ssaa {} needs a {}×{} target, beyond this device's largest framebuffer "
                          "{}×{}; reduce camera.width and camera.height or --ssaa",
                          scene.camera.width, scene.camera.height, job.ssaa, tw, th, maxW, maxH);
            SpectralPassOptions po;
            po.ssaa = job.ssaa;
            po.readback = job.readback;
            po.sampled = display;
            SpectralPass pass(*ctx, scene, rendered, po);
            std::unique_ptr<TonemapPass> tonemap;
            if (display) tonemap = std::make_unique<TonemapPass>(*ctx, pass, *plan);
            std::vector<double> shading, readback;
            for (int f = 0; f < std::max(1, job.frames); ++f) {
                pass.draw();
                shading.push_back(pass.timings().shading_ms);
                if (display) image = tonemap->render();
                if (needCube) {
                    pass.readback(cube);
                    readback.push_back(pass.timings().readback_ms);
                } else {
                    readback.push_back(0.0);
                }
            }
            r.timings.upload_ms = pass.timings().upload_ms;
            r.timings.shading_ms = shading[0];
            r.timings.readback_ms = readback[0];
            r.timings.tonemap_ms = tonemap ? tonemap->lastMs() : 0.0;
            r.timings.frames = int(shading.size());
            r.timings.first_shading_ms = shading[0];
            if (shading.size() > 1) {
                r.timings.median_shading_ms = median({shading.begin() + 1, shading.end()});
                r.timings.median_readback_ms = median({readback.begin() + 1, readback.end()});
            }
            r.backendDescription = ctx->deviceInfo().name + ": " + pass.plan().describe();
        }
        ctx.reset();  // destroy before counting: leak reports arrive at device destruction
        r.validationErrors = vk::Context::validationErrorsAtExit();
    } else {
        t = Clock::now();
        ReferenceOptions ro;
        ro.ssaa = job.ssaa;
        ReferenceImage img = renderReference(scene, rendered, ro);
        cube = std::move(img.cube);
        if (files.edges) {
            // A pixel is an edge when it or a neighbour sees something else: there rasterization and
            // ray casting may pick different surfaces, so comparisons skip it.
            int W = cube.width, H = cube.height;
            edges.assign(size_t(W) * H, 0);
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) {
                    int32_t id = img.objectId[size_t(y) * W + x];
                    bool edge = id == kMixedId;
                    for (int dy = -1; dy <= 1 && !edge; ++dy)
                        for (int dx = -1; dx <= 1 && !edge; ++dx) {
                            int nx = x + dx, ny = y + dy;
                            if (nx >= 0 && ny >= 0 && nx < W && ny < H) edge = img.objectId[size_t(ny) * W + nx] != id;
                        }
                    edges[size_t(y) * W + x] = edge ? 255 : 0;
                }
        }
        r.timings.shading_ms = msSince(t);
        if (display) {
            t = Clock::now();
            image = tonemapReference(*plan, cube);
            r.timings.tonemap_ms = msSince(t);
        }
        r.backendDescription = fmt::format("CPU reference (double precision ray casting), {} channels, ssaa {}",
                                           rendered.grid.bands(), job.ssaa);
    }
    r.clippedPixels = image.clippedPixels;
    // linear:K: the pixels are the projections onto the basis (Peercy's result).
    if (!cube.data.empty()) projectCube(representation, cube.data, cube.bands());

    t = Clock::now();
    std::string stem = job.scene.stem().string();
    std::vector<std::pair<std::string, std::string>> provenance = {
        {"metamer:scene", job.scene.string()},
        {"metamer:backend", job.backend == Backend::Gpu ? "gpu" : "cpu"},
        {"metamer:grid", scene.grid.str()},
        {"metamer:resampling", resamplingName(scene.grid.resampling)},
        {"metamer:mode", representation.mode.name()}};
    if (files.cube && !representation.mode.spectral()) {
        // A non-spectral mode's "cube" is its channel image (RGB, or AC1C2 samples).
        std::string tag = representation.mode.name();
        std::replace(tag.begin(), tag.end(), ':', '-');
        std::filesystem::path p = job.outDir / (stem + "." + tag + ".exr");
        ImageFile f{cube.width, cube.height, representation.channelNames, provenance};
        f.attributes.push_back({"metamer:representation", representation.description});
        writeImage(p, f, cube.data);
        r.written.push_back({p, fmt::format("{} channel radiance ({}), not a spectrum", representation.mode.name(),
                                            fmt::join(representation.channelNames, ", "))});
    } else if (files.cube) {
        ExrWriteOptions wo;
        wo.half = job.half;
        wo.compression = job.compression;
        wo.extraAttributes = provenance;
        std::filesystem::path p = job.outDir / (stem + ".exr");
        r.clampedToHalf = writeSpectralExr(p, cube, wo).clampedToHalfMax;
        r.written.push_back({p, fmt::format("{}×{} px, {} bands {} nm, W·sr⁻¹·m⁻²·nm⁻¹, {}", cube.width, cube.height,
                                            cube.bands(), scene.grid.str(), job.half ? "float16" : "float32")});
    }
    if (files.png) {
        std::filesystem::path p = job.outDir / (stem + ".png");
        if (responsesOnly) {
            if (!representation.mode.spectral())
                failInput(Where{"", "--detector"}, "a custom detector needs spectra; the {} mode has none",
                          representation.mode.name());
            writeQuickLookPng(p, cube, library);
            r.written.push_back({p, fmt::format("quick look, CIE 1931 → sRGB with auto exposure: detector {} has "
                                                "no display path", plan->detector.name)});
        } else {
            ImageFile f{image.width, image.height, {"R", "G", "B"}, provenance};
            f.attributes.push_back({"ImageDescription", "metamer display image: " + plan->description});
            writeImage(p, f, image.counts, plan->display.bits);
            r.written.push_back({p, "display counts: " + plan->description});
        }
    }
    if (files.xyz && !responsesOnly) {
        std::filesystem::path p = job.outDir / (stem + ".xyz.exr");
        ImageFile f{image.width, image.height, {"X", "Y", "Z"}, provenance};
        f.attributes.push_back({"metamer:xyz", plan->xyzUnits});
        f.attributes.push_back({"metamer:integration", integrationName(plan->detector.integration)});
        f.attributes.push_back({"metamer:display", plan->description});
        writeImage(p, f, image.xyz);
        r.written.push_back({p, "XYZ, " + plan->xyzUnits});
    } else if (files.xyz) {
        r.notes.push_back(fmt::format("no XYZ output: detector {} has no colorimetric path", plan->detector.name));
    }
    if (files.responses) {
        std::filesystem::path p = job.outDir / (stem + "." + detectorFileName(plan->detector.name) + ".exr");
        ImageFile f{image.width, image.height, plan->detector.channels, provenance};
        f.attributes.push_back({"metamer:detector", plan->detector.name});
        f.attributes.push_back({"metamer:units", plan->detector.units});
        f.attributes.push_back({"metamer:integration", integrationName(plan->detector.integration)});
        writeImage(p, f, image.responses);
        r.written.push_back({p, fmt::format("{} responses ({}), {}", plan->detector.name,
                                            fmt::join(plan->detector.channels, ", "), plan->detector.units)});
    }
    if (files.edges) {
        std::filesystem::path p = job.outDir / (stem + ".edges.png");
        ImageFile f{cube.width, cube.height, {"Y"}, provenance};
        writeImage(p, f, edges, 8);
        size_t n = std::count(edges.begin(), edges.end(), 255);
        r.written.push_back({p, fmt::format("edge mask: {} of {} pixels see more than one surface in their 3×3 "
                                            "neighbourhood", n, edges.size())});
    }
    r.timings.write_ms = msSince(t);
    r.timings.total_ms = msSince(start);
    return r;
}

}  // namespace metamer
