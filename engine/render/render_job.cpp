#include "render/render_job.h"

#include "io/quicklook_png.h"
#include "io/spectral_exr.h"
#include "reference/cpu_renderer.h"
#include "scene/scene_json.h"
#include "spectral/library.h"
#include "vk/context.h"

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
}  // namespace

RenderJobResult runRenderJob(const RenderJob& job) {
    RenderJobResult r;
    auto start = Clock::now();

    auto t = Clock::now();
    SpectrumLibrary library;
    Scene scene = loadScene(job.scene, library, job.overrides);
    if (job.grid) scene.grid = *job.grid;
    SceneOnGrid spectra = resampleScene(scene, scene.grid, job.coverage);
    r.timings.load_ms = msSince(t);
    r.grid = scene.grid;
    r.width = scene.camera.width;
    r.height = scene.camera.height;

    std::string stem = job.scene.stem().string();
    r.cubePath = job.outDir / (stem + ".exr");
    r.pngPath = job.outDir / (stem + ".png");

    SpectralCube cube;
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
            SpectralPass pass(*ctx, scene, spectra, po);
            std::vector<double> shading, readback;
            for (int f = 0; f < std::max(1, job.frames); ++f) {
                pass.render(cube);
                shading.push_back(pass.timings().shading_ms);
                readback.push_back(pass.timings().readback_ms);
            }
            r.timings.upload_ms = pass.timings().upload_ms;
            r.timings.shading_ms = shading[0];
            r.timings.readback_ms = readback[0];
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
        ReferenceImage img = renderReference(scene, spectra, ro);
        cube = std::move(img.cube);
        r.timings.shading_ms = msSince(t);
        r.backendDescription = fmt::format("CPU reference (double precision ray casting), {} bands, ssaa {}",
                                           scene.grid.bands(), job.ssaa);
    }

    t = Clock::now();
    ExrWriteOptions wo;
    wo.half = job.half;
    wo.compression = job.compression;
    wo.extraAttributes = {{"metamer:scene", job.scene.string()},
                          {"metamer:backend", job.backend == Backend::Gpu ? "gpu" : "cpu"}};
    ExrWriteReport wr = writeSpectralExr(r.cubePath, cube, wo);
    r.clampedToHalf = wr.clampedToHalfMax;
    if (job.quickLook) writeQuickLookPng(r.pngPath, cube, library);
    r.timings.write_ms = msSince(t);
    r.timings.total_ms = msSince(start);
    return r;
}

}  // namespace metamer
