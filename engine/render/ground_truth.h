// The ground truth beside a render's cube (docs/io.md, "Ground truth"): the reflectance and
// illumination maps from the renderer that made the cube — the GPU's band passes in the map's
// mode (shaders/spectral.frag, SPEC_QUANTITY) or the CPU reference's — so that where the mask is
// 0 the cube's radiance is reflectance × illumination band by band; and the geometry maps (ids,
// depth, normal, mask) ray cast by the reference at each pixel's central sample, for either
// backend. Tests: tests/ground_truth_test.cpp.
#pragma once

#include "reference/geometry_maps.h"
#include "render/outputs.h"
#include "render/render_job_spec.h"
#include "render/spectral_plan.h"
#include "scene/scene.h"
#include "scene/scene_on_grid.h"

#include <string>
#include <vector>

namespace metamer {

namespace vk {
class Context;
}

struct GroundTruth {
    std::vector<float> reflectance, illumination;  // pixel-interleaved bands; empty when not asked for
    GeometryMaps geometry;                          // empty when no geometry map or mask is written
    std::string legend;                             // groundTruthLegend's, with ids
    double ms = 0;                                  // what making them took
    GroundTruthImages images() const;
};

// What the renders of one job need to make the ground truth `files` asks for.
struct GroundTruthJob {
    const Scene* scene = nullptr;
    const SceneOnGrid* spectra = nullptr;  // the full spectra on the render grid (whatever the mode)
    Backend backend = Backend::Gpu;
    int ssaa = 1;
    Readback readback = Readback::Auto;
    vk::Context* context = nullptr;  // the GPU's (Backend::Gpu)
};
GroundTruth renderGroundTruth(const GroundTruthJob& job, const OutputFiles& files);

// The ids' legend, JSON: every object (mesh) and material by index with its name and, for an
// object, its material; -1 is the background.
std::string groundTruthLegend(const Scene& scene, int ssaa);

}  // namespace metamer
