// The hazard rules of vk/barrier.h, one use at a time (render/frame_pass_test.cpp tests them
// through whole frames).
#include "vk/barrier.h"

#include <gtest/gtest.h>

using namespace metamer::vk;

// Read after read in the same layout needs nothing; read after write waits once.
TEST(Barrier, ReadAfterWriteWaitsOnceReadAfterReadNever) {
    ResourceState s;
    s = advance(s, {Access::TransferDst, false}, false);
    const auto first = barrierFor(s, {Access::UniformRead}, false);
    ASSERT_TRUE(first.has_value());
    EXPECT_EQ(first->srcAccess, VkAccessFlags(VK_ACCESS_TRANSFER_WRITE_BIT));
    EXPECT_EQ(first->dstStages, VkPipelineStageFlags(VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT));
    s = advance(s, {Access::UniformRead}, false);
    EXPECT_FALSE(barrierFor(s, {Access::UniformRead}, false).has_value());
    // Another stage has not seen the write yet.
    const auto host = barrierFor(s, {Access::HostRead}, false);
    ASSERT_TRUE(host.has_value());
    EXPECT_EQ(host->srcStages, VkPipelineStageFlags(VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT));
}

// Write after read waits for the reads (execution only: no write to make available).
TEST(Barrier, WriteAfterReadWaitsForTheReaders) {
    ResourceState s = settledIn({Access::VertexInput});
    const auto b = barrierFor(s, {Access::TransferDst, false}, false);
    EXPECT_FALSE(b.has_value());  // settled: nothing read in this frame yet
    s = advance(s, {Access::VertexInput}, false);
    const auto after = barrierFor(s, {Access::TransferDst, false}, false);
    ASSERT_TRUE(after.has_value());
    EXPECT_EQ(after->srcStages, VkPipelineStageFlags(VK_PIPELINE_STAGE_VERTEX_INPUT_BIT));
    EXPECT_EQ(after->srcAccess, 0u);
}

// A use that keeps nothing transitions from UNDEFINED; one that keeps contents from where it is.
TEST(Barrier, DiscardingUsesComeFromUndefined) {
    ResourceState s = settledIn({Access::Sampled});
    const auto clear = barrierFor(s, {Access::TransferDst, false}, true);
    ASSERT_TRUE(clear.has_value());
    EXPECT_EQ(clear->oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    EXPECT_EQ(clear->newLayout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    const auto copy = barrierFor(s, {Access::TransferSrc}, true);
    ASSERT_TRUE(copy.has_value());
    EXPECT_EQ(copy->oldLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(accessLayout(Access::Sampled, true), VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);
}

// Returning to a state already held needs nothing; leaving a write unseen where the target promises
// visibility needs a barrier.
TEST(Barrier, BarrierToATargetOnlyWhenItIsNotAlreadyServed) {
    const ResourceState sampled = settledIn({Access::Sampled});
    EXPECT_FALSE(barrierTo(sampled, sampled, true).has_value());
    ResourceState written = advance(ResourceState{}, {Access::ColorAttachment, false}, true);
    const auto b = barrierTo(written, sampled, true);
    ASSERT_TRUE(b.has_value());
    EXPECT_EQ(b->srcAccess, VkAccessFlags(VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT));
    EXPECT_EQ(b->dstAccess, VkAccessFlags(VK_ACCESS_SHADER_READ_BIT));
    EXPECT_EQ(describeBarrier(*b, true),
              "after colour attachment output, its writes made visible to fragment shader; COLOR_ATTACHMENT_OPTIMAL → "
              "SHADER_READ_ONLY_OPTIMAL");
    EXPECT_TRUE(accessFits(Access::TransferSrc, false));
    EXPECT_FALSE(accessFits(Access::Sampled, false));
    EXPECT_FALSE(accessFits(Access::UniformRead, true));
}
