#include "render/display_frame.h"

#include "interface.h"

namespace metamer {

namespace {
// The response pass where it is exact: radiance is linear in each material's spectra, so a
// detector's response sums per-(material, light) responses — but radiance seen through a filter
// is a product of spectra, so a scene with transparent objects draws bands for its display image
// and the tonemap pass applies the detector to them (docs/color.md).
SpectralPassOptions responseOptions(SpectralPassOptions options, const TonemapPlan& plan, const Scene& scene) {
    if (plan.detector.weights.size() > TONEMAP_MAX_CHANNELS)
        failInput(Where{"", "--detector"}, "{} channels; the display path takes at most {}", plan.detector.weights.size(),
                  TONEMAP_MAX_CHANNELS);
    if (!scene.displayNeedsBands()) options.responseWeights = plan.detector.weights;
    options.sampled = true;
    return options;
}
}  // namespace

DisplayFrame::DisplayFrame(vk::Context& ctx, const Scene& scene, const SceneOnGrid& rendered, const TonemapPlan& plan,
                           SpectralPassOptions options, TonemapOutputs outputs)
    : pass_(ctx, scene, rendered, responseOptions(std::move(options), plan, scene)), tonemap_(ctx, pass_, plan, outputs) {
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
