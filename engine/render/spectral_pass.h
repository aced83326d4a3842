// The GPU spectral pass: rasterizes the scene into a layered RGBA32F framebuffer, 4 bands per
// layer, up to 8 layers (colour attachments) per render pass, and reads the cube back.
#pragma once

#include "scene/scene.h"
#include "scene/scene_on_grid.h"
#include "spectral/cube.h"
#include "vk/context.h"
#include "vk/resources.h"

#include <memory>
#include <string>
#include <vector>

namespace metamer {

enum class Readback {
    Auto,  // map a LINEAR host-visible image where the device allows it, else copy
    Map,   // require mapping (error if unsupported)
    Copy,  // render to an OPTIMAL image and copy to a host buffer
};

struct SpectralPassOptions {
    int ssaa = 1;  // s×s samples per pixel, box-filtered (1, 2, 3 or 4)
    Readback readback = Readback::Auto;
    bool sampled = false;  // the target is also read by a later pass (the tonemap pass)
    // Render the image in horizontal strips of this many rows (0: the whole image at once), for
    // images larger than memory: setStrip() chooses the rows, readback() returns that strip.
    int stripRows = 0;
};

// What this scene needs from the GPU: decided once, before any Vulkan object is made.
struct SpectralPassPlan {
    int bands = 0;
    int layers = 0;          // ceil(bands / 4)
    int passes = 0;          // ceil(layers / 8)
    int lightCount = 0;
    bool hasSpecular = false;
    bool hasFluorescence = false;
    bool fluorescenceSpectra = false;  // a Donaldson matrix: fluorescence as per-light spectra (interface.h)
    int ssaa = 1;
    uint32_t targetWidth = 0, targetHeight = 0;  // render-target size (× ssaa)
    bool mappedReadback = false;
    size_t targetBytes = 0;  // the layered colour target
    std::string describe() const;
};

struct SpectralPassTimings {
    double upload_ms = 0;    // buffers, images, pipelines
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
    void setStrip(int firstRow);
    int rows() const;  // rows of the target and of readback()'s cube: stripRows, or the image height

    // Moves the camera for the next draw() (the preview's orbit, pan and zoom): `camera` must keep
    // the image size the pass was made for. In strip mode, call setStrip() again afterwards.
    void setCamera(const Camera& camera);

    // Draws every band into the layered target and waits (no readback).
    void draw();
    // Reads the target drawn last into `cube` (reusing its memory when it has the right size).
    void readback(SpectralCube& cube);

    // Renders every band and returns the cube (W·sr⁻¹·m⁻²·nm⁻¹): draw() + readback().
    SpectralCube render();
    // The same into `cube`, reusing its memory when it already has the right size (repeated
    // frames then pay no allocation; timings_.readback_ms covers the allocation when it happens).
    void render(SpectralCube& cube);

    // The layered target for a later pass (options.sampled): ssaa × camera size, plan().layers
    // RGBA32F layers, in layout targetLayout() after draw() (and after readback()).
    VkImage targetImage() const;
    VkImageView targetArrayView();
    VkImageLayout targetLayout() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    SpectralPassPlan plan_;
    SpectralPassTimings timings_;
};

}  // namespace metamer
