// Pipeline barriers as one call each: where an image (all its colour layers) or a buffer is, and
// where it goes — layout, the accesses that must be finished and the ones that wait, and the
// stages they belong to. The passes describe transitions; this fills in the structs.
// Tests: through the GPU tests, with validation layers on (tests/support/gpu.h).
#pragma once

#include <vulkan/vulkan.h>

namespace metamer::vk {

// What an image is used for at one point of a command buffer.
struct ImageUse {
    VkImageLayout layout;
    VkAccessFlags access;
    VkPipelineStageFlags stage;
};

// Transitions colour layers [0, layers) of `image` (mip 0) from `from` to `to`.
void imageBarrier(VkCommandBuffer cmd, VkImage image, uint32_t layers, const ImageUse& from, const ImageUse& to);

// Makes `from`'s writes to the whole of `buffer` visible to `to`'s accesses.
void bufferBarrier(VkCommandBuffer cmd, VkBuffer buffer, VkAccessFlags fromAccess, VkPipelineStageFlags fromStage,
                   VkAccessFlags toAccess, VkPipelineStageFlags toStage);

}  // namespace metamer::vk
