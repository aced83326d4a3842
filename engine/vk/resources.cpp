#include "vk/resources.h"

#include <cstring>
#include <utility>

namespace metamer::vk {

namespace {

VkDeviceMemory allocate(const Context& ctx, VkMemoryRequirements req, VkMemoryPropertyFlags required,
                        VkMemoryPropertyFlags preferred, bool* coherent) {
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = ctx.findMemoryType(req.memoryTypeBits, required, preferred);
    VkDeviceMemory mem;
    VkResult r = vkAllocateMemory(ctx.device(), &ai, nullptr, &mem);
    if (r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY)
        failRuntime("Vulkan: out of memory allocating {:.1f} MiB ({})", req.size / 1048576.0, resultName(r));
    VK_CHECK(r);
    if (coherent)
        *coherent = ctx.memoryProperties().memoryTypes[ai.memoryTypeIndex].propertyFlags &
                    VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    return mem;
}

void invalidateAll(const Context& ctx, VkDeviceMemory mem) {
    VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
    range.memory = mem;
    range.size = VK_WHOLE_SIZE;
    VK_CHECK(vkInvalidateMappedMemoryRanges(ctx.device(), 1, &range));
}

}  // namespace

Buffer::Buffer(const Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, const char* name)
    : ctx_(&ctx), size_(size) {
    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = size;
    bci.usage = usage;
    bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VK_CHECK(vkCreateBuffer(ctx.device(), &bci, nullptr, &buffer_));
    ctx.setName(VK_OBJECT_TYPE_BUFFER, uint64_t(buffer_), name);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx.device(), buffer_, &req);
    try {
        memory_ = allocate(ctx, req, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT, VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                           &coherent_);
    } catch (...) {
        release();
        throw;
    }
    VK_CHECK(vkBindBufferMemory(ctx.device(), buffer_, memory_, 0));
    VK_CHECK(vkMapMemory(ctx.device(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        release();
        ctx_ = std::exchange(o.ctx_, nullptr);
        buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
        memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
        size_ = std::exchange(o.size_, 0);
        mapped_ = std::exchange(o.mapped_, nullptr);
        coherent_ = o.coherent_;
    }
    return *this;
}

Buffer::~Buffer() { release(); }

void Buffer::release() {
    if (!ctx_) return;
    VkDevice d = ctx_->device();
    if (buffer_) vkDestroyBuffer(d, buffer_, nullptr);
    if (memory_) vkFreeMemory(d, memory_, nullptr);  // unmaps implicitly
    buffer_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
    mapped_ = nullptr;
}

void Buffer::upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
    std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
    flush();
}

void Buffer::flush() {
    if (coherent_) return;
    VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
    range.memory = memory_;
    range.size = VK_WHOLE_SIZE;
    VK_CHECK(vkFlushMappedMemoryRanges(ctx_->device(), 1, &range));
}

void Buffer::invalidate() {
    if (!coherent_) invalidateAll(*ctx_, memory_);
}

Image::Image(const Context& ctx, const ImageDesc& desc) : ctx_(&ctx), desc_(desc) {
    VkImageCreateInfo ici{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ici.imageType = VK_IMAGE_TYPE_2D;
    ici.format = desc.format;
    ici.extent = {desc.width, desc.height, 1};
    ici.mipLevels = 1;
    ici.arrayLayers = desc.layers;
    ici.samples = VK_SAMPLE_COUNT_1_BIT;
    ici.tiling = desc.tiling;
    ici.usage = desc.usage;
    ici.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    ici.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VK_CHECK(vkCreateImage(ctx.device(), &ici, nullptr, &image_));
    ctx.setName(VK_OBJECT_TYPE_IMAGE, uint64_t(image_), desc.name);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(ctx.device(), image_, &req);
    try {
        if (desc.hostVisible)
            memory_ = allocate(ctx, req, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                               VK_MEMORY_PROPERTY_HOST_CACHED_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                               &coherent_);
        else
            memory_ = allocate(ctx, req, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, nullptr);
    } catch (...) {
        release();
        throw;
    }
    VK_CHECK(vkBindImageMemory(ctx.device(), image_, memory_, 0));
    if (desc.hostVisible) VK_CHECK(vkMapMemory(ctx.device(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
    views_.assign(desc.layers + 1, VK_NULL_HANDLE);
}

Image& Image::operator=(Image&& o) noexcept {
    if (this != &o) {
        release();
        ctx_ = std::exchange(o.ctx_, nullptr);
        desc_ = o.desc_;
        image_ = std::exchange(o.image_, VK_NULL_HANDLE);
        memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
        views_ = std::move(o.views_);
        mapped_ = std::exchange(o.mapped_, nullptr);
        coherent_ = o.coherent_;
    }
    return *this;
}

Image::~Image() { release(); }

void Image::release() {
    if (!ctx_) return;
    VkDevice d = ctx_->device();
    for (VkImageView v : views_)
        if (v) vkDestroyImageView(d, v, nullptr);
    views_.clear();
    if (image_) vkDestroyImage(d, image_, nullptr);
    if (memory_) vkFreeMemory(d, memory_, nullptr);
    image_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
    mapped_ = nullptr;
}

VkImageView Image::layerView(uint32_t layer) {
    bool all = layer == ~0u;
    uint32_t slot = all ? desc_.layers : layer;
    if (views_[slot]) return views_[slot];
    bool depth = desc_.format == VK_FORMAT_D32_SFLOAT;
    VkImageViewCreateInfo vci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vci.image = image_;
    vci.viewType = all ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
    vci.format = desc_.format;
    vci.subresourceRange = {VkImageAspectFlags(depth ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT),
                            0, 1, all ? 0 : layer, all ? desc_.layers : 1};
    VK_CHECK(vkCreateImageView(ctx_->device(), &vci, nullptr, &views_[slot]));
    return views_[slot];
}

void Image::invalidate() {
    if (!coherent_ && memory_) invalidateAll(*ctx_, memory_);
}

bool supportsLinearRenderTarget(const Context& ctx, VkFormat format, uint32_t width, uint32_t height,
                                uint32_t layers, bool sampled) {
    VkFormatProperties fp;
    vkGetPhysicalDeviceFormatProperties(ctx.physicalDevice(), format, &fp);
    if (!(fp.linearTilingFeatures & VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT)) return false;
    if (sampled && !(fp.linearTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT)) return false;
    if (!(fp.linearTilingFeatures & VK_FORMAT_FEATURE_TRANSFER_DST_BIT)) return false;  // cleared by a transfer
    VkImageUsageFlags usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                              (sampled ? VK_IMAGE_USAGE_SAMPLED_BIT : 0);
    VkImageFormatProperties ip;
    VkResult r = vkGetPhysicalDeviceImageFormatProperties(
        ctx.physicalDevice(), format, VK_IMAGE_TYPE_2D, VK_IMAGE_TILING_LINEAR, usage, 0, &ip);
    if (r != VK_SUCCESS) return false;
    if (ip.maxArrayLayers < layers || ip.maxExtent.width < width || ip.maxExtent.height < height) return false;
    // Host-visible memory must be able to back it.
    for (uint32_t i = 0; i < ctx.memoryProperties().memoryTypeCount; ++i)
        if (ctx.memoryProperties().memoryTypes[i].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) return true;
    return false;
}

}  // namespace metamer::vk
