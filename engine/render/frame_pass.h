// One pass of a frame, declared: its name, what it reads and writes and how its shader is
// specialized (in words, for people), its render pass (described in vk/render_pass.h), framebuffer, area and clear values, and a function
// that records its draws inside the render pass. The spectral frame (render/spectral_resources.h:
// depth pre-pass, lobe pass, band or response passes), the shadow maps (render/shadow_pass.cpp: a
// pass per layer) and the tonemap pass (render/tonemap_pass.cpp) are lists of these, recorded by
// recordFramePass. Tests: through every GPU test (validation layers on).
#pragma once

#include <vulkan/vulkan.h>

#include <functional>
#include <string>
#include <vector>

namespace metamer {

struct FramePass {
    std::string name;           // "depth pre-pass", "band pass 2", "shadow map layer 3", "tonemap"
    std::string reads, writes;  // in words: what it takes and what it leaves for the next pass
    std::string specialization;  // how its shader is specialized, in words ("LOBE_WRITE; a pipeline per material kind")
    VkRenderPass renderPass = VK_NULL_HANDLE;
    VkFramebuffer framebuffer = VK_NULL_HANDLE;
    VkExtent2D extent{0, 0};
    std::vector<VkClearValue> clears;                // one per attachment, colours first
    std::function<void(VkCommandBuffer)> record;     // its draws, inside the render pass
};

// Begins the pass's render pass over its extent with its clears, records its draws, ends it.
void recordFramePass(VkCommandBuffer cmd, const FramePass& pass);

// "a → b → c": the passes' names in order.
std::string describeFramePasses(const std::vector<FramePass>& passes);

}  // namespace metamer
