// Graphics pipelines with the state every Metamer pass shares: fixed viewport, no culling (two-
// sided surfaces), no blending (unless multiplied), one sample. Each pass states only what differs.
// Tests: through the GPU tests, with validation layers on.
#pragma once

#include "vk/check.h"
#include "vk/handle.h"

#include <array>
#include <type_traits>
#include <vector>

namespace metamer::vk {

// The specialization of a struct whose 4-byte fields are constant ids 0, 1, … in order (interface.h's
// *Specialization structs): the map is derived from the struct's size, so a field added there is
// mapped here without restating the count. `spec` must outlive the pipeline's creation.
template <class Spec>
VkSpecializationInfo specializationOf(const Spec& spec) {
    static_assert(sizeof(Spec) % 4 == 0 && std::is_trivially_copyable_v<Spec>, "one 4-byte field per constant id");
    static const std::array<VkSpecializationMapEntry, sizeof(Spec) / 4> entries = [] {
        std::array<VkSpecializationMapEntry, sizeof(Spec) / 4> e{};
        for (uint32_t id = 0; id < e.size(); ++id) e[id] = {id, id * 4, 4};
        return e;
    }();
    return {uint32_t(entries.size()), entries.data(), sizeof(Spec), &spec};
}

VkShaderModule createShaderModule(VkDevice device, const uint32_t* code, size_t bytes);

// A one-layer framebuffer of `views` (in the render pass's attachment order), width × height.
OwnedFramebuffer createFramebuffer(VkDevice device, VkRenderPass renderPass, const std::vector<VkImageView>& views,
                                   uint32_t width, uint32_t height);

struct GraphicsPipelineDesc {
    VkRenderPass renderPass = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkShaderModule vertex = VK_NULL_HANDLE;
    VkShaderModule fragment = VK_NULL_HANDLE;  // none: a depth-only pipeline
    const VkSpecializationInfo* fragmentSpecialization = nullptr;
    std::vector<VkVertexInputBindingDescription> bindings;
    std::vector<VkVertexInputAttributeDescription> attributes;
    uint32_t width = 0, height = 0;
    uint32_t colorAttachments = 0;
    bool depthTest = false, depthWrite = false;
    VkCompareOp depthCompare = VK_COMPARE_OP_LESS;
    // Depth bias (the shadow-map pass): enabled when either factor is non-zero.
    float depthBiasConstant = 0.0f, depthBiasSlope = 0.0f;
    // Front faces are counter-clockwise seen from their normal side (scene/scene.h). Vulkan
    // judges winding in y-down framebuffer space; the projections' y flip cancels that.
    VkFrontFace frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    VkCullModeFlags cullMode = VK_CULL_MODE_NONE;  // two-sided shading: back faces are visible
    VkPipelineCache cache = VK_NULL_HANDLE;  // Context::pipelineCache()
    // Every colour attachment becomes destination × source (the transmission pass's filters), or
    // destination + source (the coloured shadows' optical depths).
    bool multiplyBlend = false, addBlend = false;
};

VkPipeline createGraphicsPipeline(VkDevice device, const GraphicsPipelineDesc& desc);

}  // namespace metamer::vk
