#include "vk/render_pass.h"

#include "vk/check.h"

namespace metamer::vk {

namespace {

VkAttachmentDescription description(const AttachmentDesc& a) {
    VkAttachmentDescription d{};
    d.format = a.format;
    d.samples = VK_SAMPLE_COUNT_1_BIT;
    d.loadOp = a.load;
    d.storeOp = a.store;
    d.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    d.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    d.initialLayout = a.initial;
    d.finalLayout = a.final;
    return d;
}

}  // namespace

AttachmentDesc attachmentFor(VkFormat format, Access access, VkAttachmentLoadOp load, VkAttachmentStoreOp store) {
    const bool depth = access == Access::DepthAttachment;
    const VkImageLayout layout = accessLayout(access, depth);
    return {format, load, store, layout, layout};
}

RenderPassInfo::RenderPassInfo(const RenderPassDesc& desc) {
    for (uint32_t i = 0; i < desc.colors.size(); ++i) {
        attachments.push_back(description(desc.colors[i]));
        colorRefs.push_back({i, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL});
    }
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = uint32_t(colorRefs.size());
    subpass.pColorAttachments = colorRefs.empty() ? nullptr : colorRefs.data();
    if (desc.depth) {
        depthRef = {uint32_t(attachments.size()), VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
        attachments.push_back(description(*desc.depth));
        subpass.pDepthStencilAttachment = &depthRef;
    }
    info.attachmentCount = uint32_t(attachments.size());
    info.pAttachments = attachments.data();
    info.subpassCount = 1;
    info.pSubpasses = &subpass;
}

VkRenderPass createRenderPass(VkDevice device, const RenderPassDesc& desc) {
    const RenderPassInfo rp(desc);
    VkRenderPass pass = VK_NULL_HANDLE;
    VK_CHECK(vkCreateRenderPass(device, &rp.info, nullptr, &pass));
    return pass;
}

SharedHandle<VkRenderPass> sharedRenderPass(DeviceObjects& objects, const std::string& key, const RenderPassDesc& desc) {
    const RenderPassInfo rp(desc);
    return objects.renderPass(key, rp.info);
}

}  // namespace metamer::vk
