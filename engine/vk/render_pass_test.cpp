#include "vk/render_pass.h"

#include <gtest/gtest.h>

using namespace metamer::vk;

// What a band pass of the spectral pass is: two colour attachments loaded and kept, the shared
// depth after them, each staying in the layout of its use (vk::attachmentFor) — the frame's derived
// barriers make the transitions — and no subpass dependency.
TEST(RenderPass, ColoursFirstThenDepthInTheLayoutsOfTheirUses) {
    RenderPassDesc d;
    for (int i = 0; i < 2; ++i)
        d.colors.push_back(attachmentFor(VK_FORMAT_R32G32B32A32_SFLOAT, Access::ColorAttachment, VK_ATTACHMENT_LOAD_OP_LOAD));
    d.depth = attachmentFor(VK_FORMAT_D32_SFLOAT, Access::DepthAttachment, VK_ATTACHMENT_LOAD_OP_CLEAR);
    const RenderPassInfo rp(d);
    ASSERT_EQ(rp.info.attachmentCount, 3u);
    EXPECT_EQ(rp.info.pAttachments[2].format, VK_FORMAT_D32_SFLOAT);
    EXPECT_EQ(rp.info.pAttachments[2].loadOp, VK_ATTACHMENT_LOAD_OP_CLEAR);
    EXPECT_EQ(rp.info.pAttachments[0].loadOp, VK_ATTACHMENT_LOAD_OP_LOAD);
    EXPECT_EQ(rp.info.pAttachments[0].initialLayout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    EXPECT_EQ(rp.info.pAttachments[1].finalLayout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    EXPECT_EQ(rp.info.pAttachments[2].initialLayout, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    EXPECT_EQ(rp.info.pAttachments[2].finalLayout, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    for (uint32_t i = 0; i < 3; ++i) {
        EXPECT_EQ(rp.info.pAttachments[i].samples, VK_SAMPLE_COUNT_1_BIT);
        EXPECT_EQ(rp.info.pAttachments[i].stencilLoadOp, VK_ATTACHMENT_LOAD_OP_DONT_CARE);
    }
    ASSERT_EQ(rp.info.subpassCount, 1u);
    const VkSubpassDescription& sub = rp.info.pSubpasses[0];
    ASSERT_EQ(sub.colorAttachmentCount, 2u);
    EXPECT_EQ(sub.pColorAttachments[1].attachment, 1u);
    EXPECT_EQ(sub.pColorAttachments[1].layout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    ASSERT_NE(sub.pDepthStencilAttachment, nullptr);
    EXPECT_EQ(sub.pDepthStencilAttachment->attachment, 2u);
    EXPECT_EQ(rp.info.dependencyCount, 0u);
}

// The shadow maps' pass: depth only, no colour reference at all.
TEST(RenderPass, DepthOnlyHasNoColourReferences) {
    RenderPassDesc d;
    d.depth = attachmentFor(VK_FORMAT_D32_SFLOAT, Access::DepthAttachment, VK_ATTACHMENT_LOAD_OP_CLEAR);
    const RenderPassInfo rp(d);
    EXPECT_EQ(rp.info.attachmentCount, 1u);
    EXPECT_EQ(rp.info.pSubpasses[0].colorAttachmentCount, 0u);
    EXPECT_EQ(rp.info.pSubpasses[0].pColorAttachments, nullptr);
    EXPECT_EQ(rp.info.pSubpasses[0].pDepthStencilAttachment->attachment, 0u);
    EXPECT_EQ(rp.info.dependencyCount, 0u);
}
