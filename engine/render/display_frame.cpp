#include "render/display_frame.h"

#include "interface.h"

#include <algorithm>

namespace metamer {

namespace {
// Seen through sheets and media, the response pass keeps every opaque material's sums per band
// (interface.h, GpuResponseBlock::spectra) in a texel buffer: where they would pass the device's
// limit, the bands are drawn instead.
bool responseSpectraFit(vk::Context& ctx, const Scene& scene, const SceneOnGrid& rendered, size_t channels) {
    if (!scene.hasTransparency()) return true;
    const uint64_t layers = uint64_t(rendered.grid.bands() + 3) / 4;
    const uint64_t rows = (uint64_t(scene.materials.size() + 1) * std::max<size_t>(1, scene.lights.size()) * 2 *
                               (4 * ((channels + 3) / 4)) +
                           4 * MAX_OUTPUTS) * layers;
    return rows <= ctx.properties().limits.maxTexelBufferElements;
}

// The response pass where it is exact: radiance is linear in each material's spectra, so a
// detector's response sums per-(material, light) responses; seen through sheets and media it is
// τ(λ)·L(λ), and the response pass keeps its sums per band to apply τ inside them. Slabs,
// interreflection and emitters draw bands for the display image and the tonemap pass applies the
// detector to them (Scene::displayNeedsBands, docs/color.md).
SpectralPassOptions responseOptions(vk::Context& ctx, SpectralPassOptions options, const TonemapPlan& plan,
                                    const Scene& scene, const SceneOnGrid& rendered) {
    if (plan.detector.weights.size() > TONEMAP_MAX_CHANNELS)
        failInput(Where{"", "--detector"}, "{} channels; the display path takes at most {}", plan.detector.weights.size(),
                  TONEMAP_MAX_CHANNELS);
    if (!scene.displayNeedsBands() && responseSpectraFit(ctx, scene, rendered, plan.detector.weights.size()))
        options.responseWeights = plan.detector.weights;
    options.sampled = true;
    return options;
}
}  // namespace

DisplayFrame::DisplayFrame(vk::Context& ctx, const Scene& scene, const SceneOnGrid& rendered, const TonemapPlan& plan,
                           SpectralPassOptions options, TonemapOutputs outputs)
    : pass_(ctx, scene, rendered, responseOptions(ctx, std::move(options), plan, scene, rendered)), tonemap_(ctx, pass_, plan, outputs) {
    timings_.upload_ms = pass_.timings().upload_ms;
    timings_.shadow_ms = pass_.timings().shadow_ms;
}

DisplayImage DisplayFrame::render() {
    pass_.draw();
    timings_.shading_ms = pass_.timings().shading_ms;
    DisplayImage image = tonemap_.render();
    timings_.tonemap_ms = tonemap_.lastMs();
    return image;
}

}  // namespace metamer
