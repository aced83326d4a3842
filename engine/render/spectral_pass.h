// The GPU spectral pass: rasterizes the scene into a layered RGBA32F framebuffer, 4 bands per
// layer, up to 8 layers (colour attachments) per render pass, and reads the cube back. As the
// response pass (SpectralPassOptions::responseWeights) it writes a detector's channels instead of
// the bands, for the tonemap pass to read (render/display_frame.h).
// Tests: tests/gpu_known_answer_test.cpp, tests/gpu_vs_reference_test.cpp,
// tests/sampling_test.cpp, tests/strips_test.cpp, tests/numerics_test.cpp; its parts:
// render/spectral_packing_test.cpp, render/target_readback_test.cpp.
#pragma once

#include "render/frame_pass.h"
#include "render/spectral_plan.h"
#include "scene/scene.h"
#include "scene/scene_on_grid.h"
#include "spectral/cube.h"
#include "vk/barrier.h"
#include "vk/context.h"
#include "vk/resources.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace metamer {

struct SpectralPassTimings {
    double upload_ms = 0;    // buffers, images, pipelines, the shadow maps, and the interreflection
    double interreflection_ms = 0;  // of which solving the interreflection (once per scene; 0 without)
    double shadow_ms = 0;    // of which the shadow maps' depth passes (once per scene; 0 without shadowing lights)
    double shading_ms = 0;   // submit to fence
    double readback_ms = 0;  // layered target → pixel-interleaved cube (and ssaa filter)
};

class SpectralPass {
public:
    SpectralPass(vk::Context& ctx, const Scene& scene, const SceneOnGrid& spectra,
                 const SpectralPassOptions& options = {});
    ~SpectralPass();
    SpectralPass(const SpectralPass&) = delete;
    SpectralPass& operator=(const SpectralPass&) = delete;

    const SpectralPassPlan& plan() const { return plan_; }
    const SpectralPassTimings& timings() const { return timings_; }

    // Strip mode: the rows [firstRow, firstRow + stripRows) that draw() renders next (rows past the
    // image's bottom are rendered too and should be ignored).
    void setStrip(int firstRow) { setTile(0, firstRow); }
    // Tile mode (stripRows and tileColumns): the tile whose top-left pixel is (firstColumn, firstRow).
    void setTile(int firstColumn, int firstRow);
    int rows() const;     // rows of the target and of readback()'s cube: stripRows, or the image height
    int columns() const;  // its columns: tileColumns, or the image width

    // Moves the camera for the next draw() (the preview's orbit, pan and zoom): `camera` must keep
    // the image size the pass was made for. The strip or tile stays where it was.
    void setCamera(const Camera& camera);

    // Draws every band into the layered target and waits (no readback). With `afterPass`, the
    // frame's declared passes are submitted one at a time, and it is called after each with the
    // passes done and their count (render/render_progress.h: it may throw; the target then holds a
    // partial frame).
    void draw(const std::function<void(int done, int passes)>& afterPass = {});
    int framePasses() const;  // the frame's passes that draw (depth pre-pass, lobe pass, colour passes): draw()'s steps
    // Reads the target drawn last into `cube` (reusing its memory when it has the right size).
    void readback(SpectralCube& cube);

    // Renders every band and returns the cube (W·sr⁻¹·m⁻²·nm⁻¹): draw() + readback().
    SpectralCube render();
    // The same into `cube`, reusing its memory when it already has the right size (repeated
    // frames then pay no allocation; timings_.readback_ms covers the allocation when it happens).
    void render(SpectralCube& cube);

    // The layered target for a later pass (options.sampled): ssaa × camera size, plan().layers
    // RGBA32F layers, in the state targetState() after draw() (and after readback()): a later
    // frame borrows it from there and hands it back so (render/frame_pass.h, FrameResource::entry).
    VkImage targetImage() const;
    VkImageView targetArrayView();
    vk::ResourceState targetState() const;
    // The declared frame (render/frame_pass.h): its passes, resources and derived barriers (-v, tests).
    const Frame& frame() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    SpectralPassPlan plan_;
    SpectralPassTimings timings_;
};

}  // namespace metamer
