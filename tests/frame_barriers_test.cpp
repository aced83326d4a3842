// The declared frames on every bundled scene (render/frame_pass.h): the band frame, the tonemap
// frame that borrows its target, and the response pass's frame, drawn twice each with validation
// on — and what their derived barriers say, read back from the real frames.
#include "render/spectral_pass.h"
#include "render/tonemap_pass.h"
#include "render/render_setup.h"
#include "scene/scene_json.h"
#include "support/bundled_scenes.h"
#include "support/gpu.h"
#include "support/scene_builders.h"

#include <algorithm>
#include <filesystem>

using namespace metamer;
using namespace metamer::test;
namespace fs = std::filesystem;

namespace {

const SpectrumLibrary& library() {
    static SpectrumLibrary lib;
    return lib;
}

size_t passIndex(const Frame& f, const std::string& name) {
    for (size_t p = 0; p < f.size(); ++p)
        if (f.passes()[p].name == name) return p;
    ADD_FAILURE() << "no pass '" << name << "' in " << f.describe();
    return 0;
}

// The barrier pass p waits for on the resource named `resource`, or null.
const PassBarrier* waitOn(const Frame& f, size_t p, const std::string& resource) {
    for (const PassBarrier& b : f.waits(p))
        if (f.resources()[b.resource].name == resource) return &b;
    return nullptr;
}

}  // namespace

TEST(FrameBarriers, EveryBundledSceneDrawsCleanlyThroughItsDeclaredFrames) {
    const std::vector<fs::path> scenes = bundledScenes();
    ASSERT_GE(scenes.size(), 10u);
    for (const fs::path& file : scenes) {
        SCOPED_TRACE(file.filename().string());
        const Scene scene = loadScene(file, library(), {"camera.width=40", "camera.height=30"});
        const SceneOnGrid spectra = onGrid(scene);
        const uint32_t before = gpu().validationErrors();
        const TonemapPlan plan = makeScenePlan(TonemapSettings{}, scene, spectra, library());

        // The band frame and a tonemap pass borrowing its target, twice (the second frame enters
        // as the first left everything).
        SpectralPassOptions po;
        po.sampled = true;
        SpectralPass bands(gpu(), scene, spectra, po);
        TonemapPass tonemap(gpu(), bands, plan);
        for (int frame = 0; frame < 2; ++frame) {
            bands.draw();
            tonemap.render();
        }
        const Frame& f = bands.frame();
        EXPECT_EQ(f.passes().front().name, "clear");
        // Each band pass waits for the depth the pass before it tested and stored (the pre-pass's
        // writes, or the band pass before it).
        for (size_t p = 0; p < size_t(bands.plan().passes); ++p) {
            const size_t band = passIndex(f, "band pass " + std::to_string(p));
            const PassBarrier* depth = waitOn(f, band, "depth");
            ASSERT_NE(depth, nullptr) << f.describeWaits(band);
            EXPECT_NE(depth->barrier.srcAccess & VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, 0u);
            // Its target layers come from the clear (a transfer), not from another band pass.
            const PassBarrier* target = waitOn(f, band, "spectral target");
            ASSERT_NE(target, nullptr) << f.describeWaits(band);
            EXPECT_EQ(target->barrier.srcStages, VkPipelineStageFlags(VK_PIPELINE_STAGE_TRANSFER_BIT));
            EXPECT_EQ(target->firstLayer, uint32_t(p) * 8);
            if (scene.hasTransparency()) {
                // The transmission pass blends onto exactly those layers, after their colour writes.
                const size_t tp = passIndex(f, "transmission pass " + std::to_string(p));
                const PassBarrier* blended = waitOn(f, tp, "spectral target");
                ASSERT_NE(blended, nullptr) << f.describeWaits(tp);
                EXPECT_EQ(blended->barrier.srcAccess, VkAccessFlags(VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT));
                EXPECT_EQ(blended->firstLayer, target->firstLayer);
                EXPECT_EQ(blended->layerCount, target->layerCount);
            }
        }
        // The tonemap pass takes the target from where the band frame left it and hands it back.
        const Frame& t = tonemap.frame();
        const PassBarrier* borrowed = waitOn(t, 0, "spectral target");
        ASSERT_NE(borrowed, nullptr) << t.describeWaits(0);
        EXPECT_EQ(borrowed->barrier.oldLayout, bands.targetState().layout);
        EXPECT_EQ(borrowed->barrier.newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        EXPECT_TRUE(t.stateAtEnd(0) == bands.targetState());

        // The response pass's frame (what a PNG-only render and the preview draw), unless the
        // scene's transparent objects, interreflection or emitters make the display image come from bands.
        if (!scene.displayNeedsBands()) {
            SpectralPassOptions ro;
            ro.sampled = true;
            ro.responseWeights = plan.detector.weights;
            SpectralPass responses(gpu(), scene, spectra, ro);
            TonemapPass display(gpu(), responses, plan);
            for (int frame = 0; frame < 2; ++frame) {
                responses.draw();
                display.render();
            }
            // Nothing reads the response pass's target but the tonemap pass: no copy, no host read
            // (a slab's reflection is added to it last).
            const bool slab =
                std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.isSlab(); });
            EXPECT_EQ(responses.frame().passes().back().name, slab ? "slab reflection pass" : "response pass");
            EXPECT_EQ(responses.targetState().layout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        }
        EXPECT_NO_VALIDATION_ERRORS(before);
    }
}
