// The barriers a frame derives from its passes' declared uses (render/frame_pass.h): no device,
// only the derivation, with made-up handles.
#include "render/frame_pass.h"

#include "core/error.h"

#include <gtest/gtest.h>

using namespace metamer;
using vk::Access;

namespace {

VkImage fakeImage(uintptr_t n) { return reinterpret_cast<VkImage>(n); }
VkBuffer fakeBuffer(uintptr_t n) { return reinterpret_cast<VkBuffer>(n); }
VkRenderPass fakeRenderPass() { return reinterpret_cast<VkRenderPass>(uintptr_t(7)); }

FramePass pass(std::string name, std::vector<ResourceUse> uses, bool draws = true) {
    FramePass p;
    p.name = std::move(name);
    p.uses = std::move(uses);
    if (draws) p.renderPass = fakeRenderPass();
    return p;
}

constexpr VkPipelineStageFlags kDepthTests =
    VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;

}  // namespace

// The case the issue names: a pass samples what the pass before it drew. The sampler waits for the
// colour writes, and the image goes from the attachment's layout to the sampled one.
TEST(FramePass, ReadingWhatAnEarlierPassWroteWaitsForItsWrites) {
    Frame f;
    const size_t weights = f.add(FrameResource::perFrame("lobe weights", fakeImage(1)));
    f.add(pass("lobe pass", {{weights, Access::ColorAttachment, 0, kAllLayers, false}}));
    f.add(pass("band pass 0", {{weights, Access::Sampled}}));
    f.derive();
    ASSERT_EQ(f.waits(1).size(), 1u);
    const PassBarrier& b = f.waits(1)[0];
    EXPECT_EQ(b.resource, weights);
    EXPECT_EQ(b.barrier.srcStages, VkPipelineStageFlags(VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT));
    EXPECT_EQ(b.barrier.srcAccess, VkAccessFlags(VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT));
    EXPECT_EQ(b.barrier.dstStages, VkPipelineStageFlags(VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT));
    EXPECT_EQ(b.barrier.dstAccess, VkAccessFlags(VK_ACCESS_SHADER_READ_BIT));
    EXPECT_EQ(b.barrier.oldLayout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    EXPECT_EQ(b.barrier.newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(f.describeWaits(1),
              "lobe weights: after colour attachment output, its writes made visible to fragment shader; "
              "COLOR_ATTACHMENT_OPTIMAL → SHADER_READ_ONLY_OPTIMAL\n");
    // The frame is recorded again and again: the next frame's lobe pass writes over what this
    // frame's band pass sampled, so it waits for those reads, and discards the contents.
    ASSERT_EQ(f.waits(0).size(), 1u);
    const vk::Barrier& again = f.waits(0)[0].barrier;
    EXPECT_NE(again.srcStages & VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, 0u);
    EXPECT_EQ(again.oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    EXPECT_EQ(again.newLayout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    EXPECT_TRUE(f.waits(2).empty());  // nothing to hand back: the frame's own image
}

// Band passes write disjoint layers of the target: they do not wait for each other there, but the
// shared depth (tested and stored by every pass) orders them; the transmission pass that blends onto
// a band pass's layers waits for that pass's writes on those layers only.
TEST(FramePass, DisjointLayersDoNotWaitTheSharedDepthDoes) {
    Frame f;
    const size_t target = f.add(FrameResource::perFrame("spectral target", fakeImage(1), 16));
    const size_t depth = f.add(FrameResource::perFrame("depth", fakeImage(2), 1, VK_IMAGE_ASPECT_DEPTH_BIT));
    f.add(pass("clear", {{target, Access::TransferDst, 0, kAllLayers, false}}, false));
    f.add(pass("depth pre-pass", {{depth, Access::DepthAttachment, 0, kAllLayers, false}}));
    f.add(pass("band pass 0", {{target, Access::ColorAttachment, 0, 8}, {depth, Access::DepthAttachment}}));
    f.add(pass("transmission pass 0", {{target, Access::ColorAttachment, 0, 8}}));
    f.add(pass("band pass 1", {{target, Access::ColorAttachment, 8, 8}, {depth, Access::DepthAttachment}}));
    f.derive();
    // Band pass 1: the clear's write on layers 8–15 (not yet seen by an attachment) and the depth.
    const auto& band1 = f.waits(4);
    ASSERT_EQ(band1.size(), 2u);
    EXPECT_EQ(band1[0].resource, target);
    EXPECT_EQ(band1[0].firstLayer, 8u);
    EXPECT_EQ(band1[0].layerCount, 8u);
    EXPECT_EQ(band1[0].barrier.srcStages, VkPipelineStageFlags(VK_PIPELINE_STAGE_TRANSFER_BIT));
    EXPECT_EQ(band1[0].barrier.oldLayout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);  // the contents are kept
    EXPECT_EQ(band1[1].resource, depth);
    EXPECT_EQ(band1[1].barrier.srcStages, kDepthTests);
    EXPECT_EQ(band1[1].barrier.srcAccess, VkAccessFlags(VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT));
    EXPECT_EQ(band1[1].barrier.oldLayout, band1[1].barrier.newLayout);  // no transition, only a wait
    // The transmission pass: layers 0–7 after band pass 0's colour writes, reading and writing them.
    const auto& transmission = f.waits(3);
    ASSERT_EQ(transmission.size(), 1u);
    EXPECT_EQ(transmission[0].firstLayer, 0u);
    EXPECT_EQ(transmission[0].layerCount, 8u);
    EXPECT_EQ(transmission[0].barrier.srcAccess, VkAccessFlags(VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT));
    EXPECT_EQ(transmission[0].barrier.dstAccess,
              VkAccessFlags(VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT));
}

// A write read twice by the same stage is made visible once: the second reader does not wait.
TEST(FramePass, ASecondReaderOfTheSameWriteDoesNotWaitAgain) {
    Frame f;
    const size_t distance = f.add(FrameResource::perFrame("opaque distance", fakeImage(1)));
    f.add(pass("depth pre-pass", {{distance, Access::ColorAttachment, 0, kAllLayers, false}}));
    f.add(pass("transmission pass 0", {{distance, Access::Sampled}}));
    f.add(pass("transmission pass 1", {{distance, Access::Sampled}}));
    f.derive();
    EXPECT_EQ(f.waits(1).size(), 1u);
    EXPECT_TRUE(f.waits(2).empty());
}

// Resources made before the frame and only read in it cost nothing; an image made for later frames
// is left where they read it, its writes visible to them.
TEST(FramePass, SettledResourcesNeverWaitAndMadeImagesAreHandedOnSampled) {
    Frame f;
    const size_t lights = f.add(FrameResource::settled("lights", fakeBuffer(1), Access::UniformRead));
    const size_t texture = f.add(FrameResource::settled("texture 0", fakeImage(2), 3, {Access::Sampled}));
    const size_t maps = f.add(FrameResource::madeFor("shadow maps", fakeImage(3), 2, {Access::Sampled, true, true}));
    f.add(pass("shadow map layer 0", {{maps, Access::DepthAttachment, 0, 1, false}, {lights, Access::UniformRead}}));
    f.add(pass("shadow map layer 1", {{maps, Access::DepthAttachment, 1, 1, false}, {texture, Access::Sampled}}));
    f.derive();
    // Each layer comes from UNDEFINED before its pass: nothing to wait for, one transition.
    for (size_t p = 0; p < 2; ++p) {
        ASSERT_EQ(f.waits(p).size(), 1u) << p;
        EXPECT_EQ(f.waits(p)[0].resource, maps);
        EXPECT_EQ(f.waits(p)[0].firstLayer, uint32_t(p));
        EXPECT_EQ(f.waits(p)[0].barrier.srcStages, 0u);
        EXPECT_EQ(f.waits(p)[0].barrier.newLayout, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    }
    // At the end, both layers together: depth writes → fragment shader reads, read-only depth layout.
    const auto& end = f.waits(2);
    ASSERT_EQ(end.size(), 1u);
    EXPECT_EQ(end[0].layerCount, 2u);
    EXPECT_EQ(end[0].barrier.srcStages, kDepthTests);
    EXPECT_EQ(end[0].barrier.dstStages, VkPipelineStageFlags(VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT));
    EXPECT_EQ(end[0].barrier.dstAccess, VkAccessFlags(VK_ACCESS_SHADER_READ_BIT));
    EXPECT_EQ(end[0].barrier.newLayout, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);
    EXPECT_TRUE(f.stateAtEnd(maps) == vk::settledIn({Access::Sampled, true, true}));
}

// A borrowed image (the tonemap pass reading the spectral pass's target) enters as the other frame
// left it and is handed back so: sampled after its colour writes, then returned to its layout.
TEST(FramePass, ABorrowedImageIsHandedBackAsItCame) {
    Frame spectral;
    const size_t target = spectral.add(FrameResource::perFrame("spectral target", fakeImage(1), 2));
    spectral.add(pass("clear", {{target, Access::TransferDst, 0, kAllLayers, false}}, false));
    spectral.add(pass("response pass", {{target, Access::ColorAttachment}}));
    spectral.derive();
    const vk::ResourceState drawn = spectral.stateAtEnd(target);
    EXPECT_EQ(drawn.layout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);

    Frame tonemap;
    FrameResource borrowed = FrameResource::perFrame("spectral target", fakeImage(1), 2);
    borrowed.entry = borrowed.exit = drawn;
    const size_t t = tonemap.add(std::move(borrowed));
    const size_t readback = tonemap.add(FrameResource::perFrame("tonemap readback", fakeBuffer(2)));
    tonemap.add(pass("tonemap", {{t, Access::Sampled}}));
    tonemap.add(pass("tonemap readback", {{readback, Access::TransferDst}}, false));
    tonemap.add(pass("host read", {{readback, Access::HostRead}}, false));
    tonemap.derive();
    ASSERT_EQ(tonemap.waits(0).size(), 1u);  // the target after its writes (the buffer's first use is the copy's)
    EXPECT_EQ(tonemap.waits(0)[0].barrier.newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(tonemap.waits(0)[0].barrier.srcAccess, VkAccessFlags(VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT));
    // The buffer: the copy's write before the host reads it.
    ASSERT_EQ(tonemap.waits(2).size(), 1u);
    EXPECT_EQ(tonemap.waits(2)[0].barrier.srcStages, VkPipelineStageFlags(VK_PIPELINE_STAGE_TRANSFER_BIT));
    EXPECT_EQ(tonemap.waits(2)[0].barrier.dstStages, VkPipelineStageFlags(VK_PIPELINE_STAGE_HOST_BIT));
    EXPECT_EQ(tonemap.waits(2)[0].barrier.dstAccess, VkAccessFlags(VK_ACCESS_HOST_READ_BIT));
    // Handed back: SHADER_READ_ONLY → COLOR_ATTACHMENT_OPTIMAL after the fragment shader's reads,
    // scoped to the stage the spectral frame will wait on.
    const auto& back = tonemap.waits(3);
    ASSERT_EQ(back.size(), 1u);
    EXPECT_EQ(back[0].layerCount, 2u);
    EXPECT_EQ(back[0].barrier.oldLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(back[0].barrier.newLayout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    EXPECT_NE(back[0].barrier.srcStages & VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, 0u);
    EXPECT_NE(back[0].barrier.dstStages & VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0u);
    EXPECT_TRUE(tonemap.stateAtEnd(t) == drawn);
}

// What cannot be derived is said, naming the pass and the resource.
TEST(FramePass, UsesThatCannotBeDerivedAreRefusedByName) {
    auto message = [](Frame& f) {
        try {
            f.derive();
        } catch (const Error& e) {
            return e.text();
        }
        return std::string("no error");
    };
    {  // read before anything in the frame writes it, and no state declared at the start
        Frame f;
        const size_t depth = f.add(FrameResource::perFrame("depth", fakeImage(1), 1, VK_IMAGE_ASPECT_DEPTH_BIT));
        f.add(pass("band pass 0", {{depth, Access::DepthAttachment}}));
        const std::string m = message(f);
        EXPECT_NE(m.find("'band pass 0'"), std::string::npos) << m;
        EXPECT_NE(m.find("'depth'"), std::string::npos) << m;
        EXPECT_NE(m.find("no earlier pass"), std::string::npos) << m;
    }
    {  // layers outside the image
        Frame f;
        const size_t target = f.add(FrameResource::perFrame("spectral target", fakeImage(1), 4));
        f.add(pass("band pass 1", {{target, Access::ColorAttachment, 2, 8, false}}));
        const std::string m = message(f);
        EXPECT_NE(m.find("layers 2…9 of 'spectral target', which has 4"), std::string::npos) << m;
    }
    {  // an image's access on a buffer
        Frame f;
        const size_t b = f.add(FrameResource::perFrame("readback buffer", fakeBuffer(1)));
        f.add(pass("copy", {{b, Access::Sampled}}, false));
        const std::string m = message(f);
        EXPECT_NE(m.find("buffer 'readback buffer' as a sampled"), std::string::npos) << m;
    }
    {  // the same layer twice in one pass (a feedback loop)
        Frame f;
        const size_t t = f.add(FrameResource::perFrame("t", fakeImage(1), 2));
        f.add(pass("p", {{t, Access::ColorAttachment, 0, 2, false}, {t, Access::Sampled, 1, 1}}));
        const std::string m = message(f);
        EXPECT_NE(m.find("uses layer 1 of 't' twice"), std::string::npos) << m;
    }
    {  // a resource the frame does not hold
        Frame f;
        f.add(pass("p", {{3, Access::Sampled}}));
        EXPECT_NE(message(f).find("uses resource 3; the frame holds 0"), std::string::npos);
    }
}

// A pass-by-pass submission cuts the frame before each pass that draws but the first, so the clear
// goes with the first and the readback with the last: as many steps as passes that draw.
TEST(FramePass, DrawingStepsKeepTransfersWithTheirNeighbours) {
    Frame f;
    const size_t target = f.add(FrameResource::perFrame("target", fakeImage(1)));
    f.add(pass("clear", {{target, Access::TransferDst, 0, kAllLayers, false}}, false));
    f.add(pass("band pass 0", {{target, Access::ColorAttachment}}));
    f.add(pass("band pass 1", {{target, Access::ColorAttachment}}));
    f.add(pass("host read", {{target, Access::HostRead}}, false));
    f.derive();
    const auto steps = f.drawingSteps();
    ASSERT_EQ(steps.size(), 2u);
    EXPECT_EQ(steps[0], std::make_pair(size_t(0), size_t(2)));
    EXPECT_EQ(steps[1], std::make_pair(size_t(2), size_t(4)));
    EXPECT_EQ(f.describe(), "clear → band pass 0 → band pass 1 → host read");
}
