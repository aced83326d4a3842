// Buffers and images with their memory: one allocation each (scenes have a handful), freed by
// the owner's destructor. No VMA in Debian; this is all Metamer needs.
// Tests: through the GPU tests, with validation layers on.
#pragma once

#include "vk/context.h"

namespace metamer::vk {

class Buffer {
public:
    Buffer() = default;
    // Host-visible (and coherent where possible), persistently mapped.
    Buffer(const Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, const char* name);
    ~Buffer();
    Buffer(Buffer&& o) noexcept { *this = std::move(o); }
    Buffer& operator=(Buffer&& o) noexcept;

    VkBuffer handle() const { return buffer_; }
    VkDeviceSize size() const { return size_; }
    void* mapped() const { return mapped_; }
    void upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
    void flush();       // make host writes through mapped() visible to the device on non-coherent memory
    void invalidate();  // make device writes visible to the host on non-coherent memory

private:
    void release();
    const Context* ctx_ = nullptr;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkDeviceSize size_ = 0;
    void* mapped_ = nullptr;
    bool coherent_ = true;
};

struct ImageDesc {
    VkFormat format = VK_FORMAT_R32G32B32A32_SFLOAT;
    uint32_t width = 1, height = 1, layers = 1;
    VkImageUsageFlags usage = 0;
    VkImageTiling tiling = VK_IMAGE_TILING_OPTIMAL;
    bool hostVisible = false;  // LINEAR images read by mapping
    const char* name = "image";
};

class Image {
public:
    Image() = default;
    Image(const Context& ctx, const ImageDesc& desc);
    ~Image();
    Image(Image&& o) noexcept { *this = std::move(o); }
    Image& operator=(Image&& o) noexcept;

    VkImage handle() const { return image_; }
    const ImageDesc& desc() const { return desc_; }
    // A view of one layer (2D) or of all layers (2D array) when layer == ~0u. Owned by the Image.
    VkImageView layerView(uint32_t layer);
    void* mapped() const { return mapped_; }
    void invalidate();

private:
    void release();
    const Context* ctx_ = nullptr;
    ImageDesc desc_;
    VkImage image_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    std::vector<VkImageView> views_;  // per layer, created lazily
    void* mapped_ = nullptr;
    bool coherent_ = true;
};

// Whether the device can render into a LINEAR host-visible 2D-array image of this size (so the
// cube can be read back by mapping instead of copying); `sampled` also requires sampling it.
bool supportsLinearRenderTarget(const Context& ctx, VkFormat format, uint32_t width, uint32_t height,
                                uint32_t layers, bool sampled = false);

}  // namespace metamer::vk
