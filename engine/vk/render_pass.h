// Render passes described as data. Every pass Metamer draws — the spectral depth pre-pass and band
// passes, the lobe pass, the shadow maps, the tonemap pass, the preview's UI pass — is a
// RenderPassDesc: its attachments (colour ones first, then depth), and how each is loaded, stored
// and left. None carries a subpass dependency: every pass is one of a declared frame
// (render/frame_pass.h), whose derived barriers order it with what comes before and after. This
// is the one place that turns one into a VkRenderPassCreateInfo; no file outside vk/ fills one.
// Tests: engine/vk/render_pass_test.cpp, and every GPU test (validation layers on).
#pragma once

#include "vk/barrier.h"
#include "vk/device_objects.h"

#include <vulkan/vulkan.h>

#include <optional>
#include <string>
#include <vector>

namespace metamer::vk {

struct AttachmentDesc {
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkAttachmentLoadOp load = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    VkAttachmentStoreOp store = VK_ATTACHMENT_STORE_OP_STORE;
    VkImageLayout initial = VK_IMAGE_LAYOUT_UNDEFINED;
    VkImageLayout final = VK_IMAGE_LAYOUT_UNDEFINED;
};

// An attachment that stays in the layout of its use (vk/barrier.h, accessLayout): for passes of
// a declared frame (render/frame_pass.h), whose derived barriers make every transition and every
// wait before and after the render pass, so the render pass itself makes none.
AttachmentDesc attachmentFor(VkFormat format, Access access, VkAttachmentLoadOp load,
                             VkAttachmentStoreOp store = VK_ATTACHMENT_STORE_OP_STORE);

struct RenderPassDesc {
    std::vector<AttachmentDesc> colors;   // used as COLOR_ATTACHMENT_OPTIMAL, at indices 0..n−1
    std::optional<AttachmentDesc> depth;  // used as DEPTH_STENCIL_ATTACHMENT_OPTIMAL, after the colours
};

// The create-info's parts, kept alive together (pointers into this object).
struct RenderPassInfo {
    std::vector<VkAttachmentDescription> attachments;
    std::vector<VkAttachmentReference> colorRefs;
    VkAttachmentReference depthRef{};
    VkSubpassDescription subpass{};
    VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    explicit RenderPassInfo(const RenderPassDesc& desc);
    RenderPassInfo(const RenderPassInfo&) = delete;
    RenderPassInfo& operator=(const RenderPassInfo&) = delete;
};

// A new render pass the caller owns.
VkRenderPass createRenderPass(VkDevice device, const RenderPassDesc& desc);
// The pass shared under `key` through the device's object cache (made the first time).
SharedHandle<VkRenderPass> sharedRenderPass(DeviceObjects& objects, const std::string& key, const RenderPassDesc& desc);

}  // namespace metamer::vk
