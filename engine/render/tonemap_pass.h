// The GPU tonemap pass: reads the spectral pass's layered target and evaluates the display path
// (color/tonemap.h) per output pixel: detector responses, XYZ, adapted display counts. Shared by
// `metamer render` and the preview window; checked against color/tonemap_reference.
// Tests: tests/tonemap_test.cpp (against color/tonemap_reference), tests/representation_test.cpp,
// the goldens.
#pragma once

#include "render/frame_pass.h"

#include "color/tonemap.h"
#include "render/spectral_pass.h"
#include "vk/context.h"

#include <memory>

namespace metamer {

// What render() reads back: the rest stays empty in its DisplayImage (a display PNG needs only
// the counts; every attachment is still drawn).
struct TonemapOutputs {
    bool counts = true;     // counts and the clip mask
    bool xyz = true;
    bool responses = true;
};

class TonemapPass {
public:
    // `source` must have been made with SpectralPassOptions::sampled = true and outlive this.
    TonemapPass(vk::Context& ctx, SpectralPass& source, const TonemapPlan& plan, TonemapOutputs outputs = {});
    ~TonemapPass();
    TonemapPass(const TonemapPass&) = delete;
    TonemapPass& operator=(const TonemapPass&) = delete;

    // Runs the pass on what source.draw() drew last, waits, and reads the outputs back.
    DisplayImage render();
    double lastMs() const { return lastMs_; }
    // The declared frame (render/frame_pass.h): tonemap, readback copy, host read (tests).
    const Frame& frame() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    double lastMs_ = 0;
};

}  // namespace metamer
