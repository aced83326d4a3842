#include "render/display_frame.h"

#include "interface.h"

namespace metamer {

namespace {
SpectralPassOptions responseOptions(SpectralPassOptions options, const TonemapPlan& plan) {
    if (plan.detector.weights.size() > TONEMAP_MAX_CHANNELS)
        failInput(Where{"", "--detector"}, "{} channels; the display path takes at most {}", plan.detector.weights.size(),
                  TONEMAP_MAX_CHANNELS);
    options.responseWeights = plan.detector.weights;
    options.sampled = true;
    return options;
}
}  // namespace

DisplayFrame::DisplayFrame(vk::Context& ctx, const Scene& scene, const SceneOnGrid& rendered, const TonemapPlan& plan,
                           SpectralPassOptions options, TonemapOutputs outputs)
    : pass_(ctx, scene, rendered, responseOptions(std::move(options), plan)), tonemap_(ctx, pass_, plan, outputs) {
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
