#include "render/render_job.h"

#include "io/image_file.h"
#include "io/quicklook_png.h"
#include "io/spectral_exr.h"
#include "reference/cpu_renderer.h"
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

}  // namespace

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
    SpectrumLibrary library;
    Scene scene = loadScene(job.scene, library, job.overrides);
    if (job.grid) scene.grid = *job.grid;
    SceneOnGrid spectra = resampleScene(scene, scene.grid, job.coverage);
    Representation representation =
        makeRepresentation(parseMode(job.mode, Where{"", "--mode"}), scene.grid, library, &spectra);
    // What the renderers see: the spectra in the mode's channels (the same spectra in full mode).
    SceneOnGrid rendered = represent(spectra, representation, scene);
    OutputFiles files;
    TonemapSettings settings = tonemapSettings(job, scene, &files);
    bool display = files.png || files.xyz || files.responses;
    std::optional<TonemapPlan> plan;
    if (display) {
        // Names given in the scene are reported against the scene's output block.
        Where sceneOut = scene.output.where.file.empty() ? Where{scene.file.string(), "output"} : scene.output.where;
        try {
            plan = makeTonemapPlan(settings, scene, spectra, library, &representation);
        } catch (const Error& e) {
            bool fromScene = (!job.detector && scene.output.detector && e.where().key == "--detector") ||
                             (!job.display && scene.output.display && e.where().key == "--display");
            if (!fromScene) throw;
            throw Error(e.code(), sceneOut.child(e.where().key == "--detector" ? "detector" : "display"), e.message());
        }
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

    SpectralCube cube;
    DisplayImage image;
    std::vector<uint16_t> edges;
    if (job.backend == Backend::Gpu) {
        vk::ContextOptions co = vk::contextOptionsFromEnvironment();
        co.validation = co.validation || job.validation;
        if (!job.device.empty()) co.device = job.device;
        co.verbose = job.verbose;
        auto ctx = std::make_unique<vk::Context>(co);
        {
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
