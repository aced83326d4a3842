// The display path of a frame that never writes the bands: the response pass (the spectral pass
// writing the detector's channels, summed from per-(material, light) responses computed once in
// double) followed by the tonemap pass, which adapts and applies the display model as after the
// band passes. Used whenever the cube itself is not asked for: `metamer render --write
// png|xyz|responses`, strips of such renders, the preview and `metamer bench`. Every detector,
// adaptation, display and representation mode goes through it: a mode's channels are bands to it.
// docs/color.md, "The response pass". Tests: tests/response_pass_test.cpp (against the cube path).
#pragma once

#include "color/tonemap.h"
#include "render/spectral_pass.h"
#include "render/tonemap_pass.h"
#include "scene/scene.h"
#include "scene/scene_on_grid.h"
#include "vk/context.h"

#include <memory>

namespace metamer {

struct DisplayFrameTimings {
    double upload_ms = 0;   // packing the responses (double precision) and the GPU objects
    double shadow_ms = 0;   // of which the shadow maps' depth passes
    double shading_ms = 0;  // the response pass, submit to fence
    double tonemap_ms = 0;  // the tonemap pass and the read-back of its display image
};

class DisplayFrame {
public:
    // `rendered` is the scene on its grid in the representation's channels, `plan` the display
    // plan for them (its detector's weights are on those channels); both must outlive this.
    // `options` gives ssaa, strips; its responseWeights and sampled are set here.
    DisplayFrame(vk::Context& ctx, const Scene& scene, const SceneOnGrid& rendered, const TonemapPlan& plan,
                 SpectralPassOptions options = {}, TonemapOutputs outputs = {});

    // As SpectralPass's: the camera (same image size) and, in strip mode, the strip drawn next.
    void setCamera(const Camera& camera) { pass_.setCamera(camera); }
    void setStrip(int firstRow) { pass_.setStrip(firstRow); }
    int rows() const { return pass_.rows(); }

    // Draws the responses and tonemaps them: responses, XYZ, counts, as TonemapPass::render().
    DisplayImage render();

    const SpectralPassPlan& passPlan() const { return pass_.plan(); }
    const DisplayFrameTimings& timings() const { return timings_; }

private:
    SpectralPass pass_;
    TonemapPass tonemap_;
    DisplayFrameTimings timings_;
};

}  // namespace metamer
