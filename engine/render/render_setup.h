// What a GPU frame of a render job is made from, shared by the offline render
// (render/render_job.cpp) and the preview window (engine/preview): the scene loaded with the
// job's --set overrides and --grid, its spectra on the grid, the representation (--mode) and the
// spectra the renderers see, the display plan, and the Vulkan context options.
// Tests: tests/tonemap_test.cpp, tests/representation_test.cpp, engine/preview/view_test.cpp.
#pragma once

#include "color/tonemap.h"
#include "render/render_job_spec.h"
#include "represent/representation.h"
#include "scene/scene.h"
#include "scene/scene_on_grid.h"
#include "spectral/library.h"
#include "vk/context.h"

#include <memory>

namespace metamer {

struct LoadedScene {
    SpectrumLibrary library;
    Scene scene;                    // as read, with the job's overrides
    Grid grid;                      // the render grid: job.grid, else scene.grid; job.resampling, else the scene's rule
    SceneOnGrid spectra;            // every spectrum on `grid` by its resampling rule (full)
    Representation representation;  // job.mode
    SceneOnGrid rendered;           // what the renderers see: the spectra in the mode's channels
};

// Reads job.scene with job.overrides (and job.allowOutsidePaths), puts it on job.grid (else the
// scene's grid) with job.coverage, and represents it in job.mode. Held by pointer: the GPU passes
// keep references to its members.
std::unique_ptr<LoadedScene> loadJobScene(const RenderJob& job);

// The display plan of a scene: its reference white (scene/scene_white.h) on `spectra.grid`, and the
// channels of `representation` (full when null) — makeTonemapPlan with what it needs of the scene.
TonemapPlan makeScenePlan(const TonemapSettings& settings, const Scene& scene, const SceneOnGrid& spectra,
                          const SpectrumLibrary& library, const Representation* representation = nullptr);

// makeScenePlan for the job's display settings (tonemapSettings()), with each error blamed where
// the failing choice was made: the scene's output block, the flag, or a csv: detector's own file.
TonemapPlan makeJobTonemapPlan(const RenderJob& job, const LoadedScene& loaded, const TonemapSettings& settings);

// The environment's context options (METAMER_VALIDATION, METAMER_DEVICE) with the job's
// --validation, --device and --verbose.
vk::ContextOptions jobContextOptions(const RenderJob& job);

}  // namespace metamer
