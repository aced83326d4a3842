#include "vk/barrier.h"

namespace metamer::vk {

void imageBarrier(VkCommandBuffer cmd, VkImage image, uint32_t layers, const ImageUse& from, const ImageUse& to) {
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.srcAccessMask = from.access;
    b.dstAccessMask = to.access;
    b.oldLayout = from.layout;
    b.newLayout = to.layout;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, layers};
    vkCmdPipelineBarrier(cmd, from.stage, to.stage, 0, 0, nullptr, 0, nullptr, 1, &b);
}

void bufferBarrier(VkCommandBuffer cmd, VkBuffer buffer, VkAccessFlags fromAccess, VkPipelineStageFlags fromStage,
                   VkAccessFlags toAccess, VkPipelineStageFlags toStage) {
    VkBufferMemoryBarrier b{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
    b.srcAccessMask = fromAccess;
    b.dstAccessMask = toAccess;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.buffer = buffer;
    b.size = VK_WHOLE_SIZE;
    vkCmdPipelineBarrier(cmd, fromStage, toStage, 0, 0, nullptr, 1, &b, 0, nullptr);
}

}  // namespace metamer::vk
