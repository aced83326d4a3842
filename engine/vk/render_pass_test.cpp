#include "vk/render_pass.h"

#include <gtest/gtest.h>

using namespace metamer::vk;

// What a band pass of the spectral pass is: two colour attachments loaded and kept, the shared
// depth after them, waiting for the pre-pass's depth writes.
TEST(RenderPass, ColoursFirstThenDepthWithTheirLayoutsAndDependencies) {
    RenderPassDesc d;
    for (int i = 0; i < 2; ++i)
        d.colors.push_back({VK_FORMAT_R32G32B32A32_SFLOAT, VK_ATTACHMENT_LOAD_OP_LOAD, VK_ATTACHMENT_STORE_OP_STORE,
                            VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL});
    d.depth = AttachmentDesc{VK_FORMAT_D32_SFLOAT, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_STORE,
                             VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    d.dependencies.push_back({true, VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT, VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT,
                              VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT});
    d.dependencies.push_back({false, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                              VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT});
    const RenderPassInfo rp(d);
    ASSERT_EQ(rp.info.attachmentCount, 3u);
    EXPECT_EQ(rp.info.pAttachments[2].format, VK_FORMAT_D32_SFLOAT);
    EXPECT_EQ(rp.info.pAttachments[2].loadOp, VK_ATTACHMENT_LOAD_OP_CLEAR);
    EXPECT_EQ(rp.info.pAttachments[0].initialLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(rp.info.pAttachments[1].finalLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
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
    ASSERT_EQ(rp.info.dependencyCount, 2u);
    EXPECT_EQ(rp.info.pDependencies[0].srcSubpass, VK_SUBPASS_EXTERNAL);
    EXPECT_EQ(rp.info.pDependencies[0].dstSubpass, 0u);
    EXPECT_EQ(rp.info.pDependencies[1].srcSubpass, 0u);
    EXPECT_EQ(rp.info.pDependencies[1].dstSubpass, VK_SUBPASS_EXTERNAL);
    EXPECT_EQ(rp.info.pDependencies[1].dstAccessMask, VK_ACCESS_SHADER_READ_BIT);
}

// The shadow maps' pass: depth only, no colour reference at all.
TEST(RenderPass, DepthOnlyHasNoColourReferences) {
    RenderPassDesc d;
    d.depth = AttachmentDesc{VK_FORMAT_D32_SFLOAT, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_STORE,
                             VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL};
    const RenderPassInfo rp(d);
    EXPECT_EQ(rp.info.attachmentCount, 1u);
    EXPECT_EQ(rp.info.pSubpasses[0].colorAttachmentCount, 0u);
    EXPECT_EQ(rp.info.pSubpasses[0].pColorAttachments, nullptr);
    EXPECT_EQ(rp.info.pSubpasses[0].pDepthStencilAttachment->attachment, 0u);
    EXPECT_EQ(rp.info.dependencyCount, 0u);
}
