#include "preview/presenter.h"

#include "render/frame_pass.h"

#include <algorithm>
#include <cstring>

namespace metamer::preview {

Presenter::Presenter(vk::Context& ctx, const Window& window, bool immediate) : ctx_(ctx), window_(window) {
    swapchain_ = std::make_unique<Swapchain>(ctx, window.framebufferSize(), immediate);
    VkDevice d = ctx.device();
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = ctx.commandPool();
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VK_CHECK(vkAllocateCommandBuffers(d, &ai, &cmd_));
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    fi.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    VK_CHECK(vkCreateFence(d, &fi, nullptr, &fence_));
    VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VK_CHECK(vkCreateSemaphore(d, &si, nullptr, &acquired_));
}

Presenter::~Presenter() {
    VkDevice d = ctx_.device();
    vkDeviceWaitIdle(d);
    for (VkSemaphore s : rendered_) vkDestroySemaphore(d, s, nullptr);
    if (acquired_) vkDestroySemaphore(d, acquired_, nullptr);
    if (fence_) vkDestroyFence(d, fence_, nullptr);
    if (cmd_) vkFreeCommandBuffers(d, ctx_.commandPool(), 1, &cmd_);
    swapchain_.reset();
}

void Presenter::setImages(const std::vector<ShownImage>& images) {
    VkDeviceSize bytes = 0;
    for (const ShownImage& im : images) bytes += VkDeviceSize(im.width) * im.height * 4;
    // The previous frame may still read the buffer.
    VK_CHECK(vkWaitForFences(ctx_.device(), 1, &fence_, VK_TRUE, UINT64_MAX));
    if (bytes > upload_.size())
        upload_ = vk::Buffer(ctx_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, "preview display images");
    regions_.clear();
    VkDeviceSize offset = 0;
    for (const ShownImage& im : images) {
        VkDeviceSize n = VkDeviceSize(im.width) * im.height * 4;
        if (!im.pixels || im.pixels->size() != n)
            failRuntime("preview: a {}×{} display image needs {} bytes", im.width, im.height, n);
        upload_.upload(im.pixels->data(), n, offset);
        regions_.push_back({im.x, im.y, im.width, im.height, offset});
        offset += n;
    }
}

void Presenter::copyImages(VkCommandBuffer cmd, VkImage image) const {
    const VkExtent2D ext = swapchain_->extent();
    for (const Region& r : regions_) {
        // The part of the image inside the window.
        int x0 = std::max(r.x, 0), y0 = std::max(r.y, 0);
        int x1 = std::min(r.x + r.width, int(ext.width)), y1 = std::min(r.y + r.height, int(ext.height));
        if (x1 <= x0 || y1 <= y0) continue;
        VkBufferImageCopy c{};
        c.bufferOffset = r.offset + (VkDeviceSize(y0 - r.y) * r.width + VkDeviceSize(x0 - r.x)) * 4;
        c.bufferRowLength = uint32_t(r.width);
        c.bufferImageHeight = uint32_t(r.height);
        c.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        c.imageOffset = {x0, y0, 0};
        c.imageExtent = {uint32_t(x1 - x0), uint32_t(y1 - y0), 1};
        vkCmdCopyBufferToImage(cmd, upload_.handle(), image, vk::accessLayout(vk::Access::TransferDst), 1, &c);
    }
}

bool Presenter::frame(const std::function<void(VkCommandBuffer)>& ui, bool readBack) {
    VkDevice d = ctx_.device();
    VkExtent2D size = window_.framebufferSize();
    if (size.width == 0 || size.height == 0) return false;  // minimized
    VK_CHECK(vkWaitForFences(d, 1, &fence_, VK_TRUE, UINT64_MAX));
    if (stale_ || size.width != swapchain_->extent().width || size.height != swapchain_->extent().height) {
        swapchain_->recreate(size);
        stale_ = false;
    }
    if (rendered_.size() != swapchain_->imageCount()) {
        for (VkSemaphore s : rendered_) vkDestroySemaphore(d, s, nullptr);
        rendered_.assign(swapchain_->imageCount(), VK_NULL_HANDLE);
        VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        for (VkSemaphore& s : rendered_) VK_CHECK(vkCreateSemaphore(d, &si, nullptr, &s));
    }
    uint32_t index = 0;
    VkResult r = vkAcquireNextImageKHR(d, swapchain_->handle(), UINT64_MAX, acquired_, VK_NULL_HANDLE, &index);
    if (r == VK_ERROR_OUT_OF_DATE_KHR) {
        stale_ = true;
        return false;
    }
    if (r == VK_SUBOPTIMAL_KHR) stale_ = true;
    else VK_CHECK(r);

    VK_CHECK(vkResetCommandBuffer(cmd_, 0));
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(cmd_, &bi));
    // The frame (render/frame_pass.h): clear, copy the display images in, the UI over them, the
    // screenshot's copy; the image handed to presentation. The acquired image comes with the
    // acquire semaphore, waited for at the transfer stage: the first transition waits there too.
    VkImage image = swapchain_->image(index);
    const VkExtent2D ext = swapchain_->extent();
    const bool reading = readBack && swapchain_->readable();
    using vk::Access;
    Frame f;
    FrameResource shown = FrameResource::perFrame("swapchain image", image);
    shown.entry = vk::ResourceState{VK_IMAGE_LAYOUT_UNDEFINED, 0, 0, VK_PIPELINE_STAGE_TRANSFER_BIT};
    shown.exit = vk::settledIn({Access::Present});
    const size_t target = f.add(std::move(shown));
    f.add(FramePass{"clear", "vkCmdClearColorImage", {{target, Access::TransferDst, 0, kAllLayers, false}}, VK_NULL_HANDLE,
                    VK_NULL_HANDLE, {}, {}, [image](VkCommandBuffer cmd) {
                        const VkClearColorValue background{{0.06f, 0.06f, 0.06f, 1.0f}};
                        const VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
                        vkCmdClearColorImage(cmd, image, vk::accessLayout(Access::TransferDst), &background, 1, &all);
                    }});
    if (!regions_.empty()) {
        const size_t upload = f.add(FrameResource::settled("display images", upload_.handle(), Access::TransferSrc));
        f.add(FramePass{"display images", "vkCmdCopyBufferToImage", {{target, Access::TransferDst}, {upload, Access::TransferSrc}},
                        VK_NULL_HANDLE, VK_NULL_HANDLE, {}, {}, [this, image](VkCommandBuffer cmd) { copyImages(cmd, image); }});
    }
    f.add(FramePass{"ui", "Dear ImGui", {{target, Access::ColorAttachment}}, swapchain_->renderPass(),
                    swapchain_->framebuffer(index), ext, {}, ui});
    if (reading) {
        VkDeviceSize bytes = VkDeviceSize(ext.width) * ext.height * 4;
        if (readback_.size() < bytes)
            readback_ = vk::Buffer(ctx_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, "preview screenshot");
        const size_t shot = f.add(FrameResource::perFrame("screenshot", readback_.handle()));
        f.add(FramePass{"screenshot copy", "vkCmdCopyImageToBuffer", {{target, Access::TransferSrc}, {shot, Access::TransferDst}},
                        VK_NULL_HANDLE, VK_NULL_HANDLE, {}, {}, [this, image, ext](VkCommandBuffer cmd) {
                            VkBufferImageCopy c{};
                            c.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                            c.imageExtent = {ext.width, ext.height, 1};
                            vkCmdCopyImageToBuffer(cmd, image, vk::accessLayout(Access::TransferSrc), readback_.handle(), 1, &c);
                        }});
        f.add(FramePass{"host read", "the host maps the screenshot", {{shot, Access::HostRead}}});
    }
    f.derive();
    recordFrame(cmd_, f);
    VK_CHECK(vkEndCommandBuffer(cmd_));

    VK_CHECK(vkResetFences(d, 1, &fence_));
    VkPipelineStageFlags wait = VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.waitSemaphoreCount = 1;
    si.pWaitSemaphores = &acquired_;
    si.pWaitDstStageMask = &wait;
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd_;
    si.signalSemaphoreCount = 1;
    si.pSignalSemaphores = &rendered_[index];
    VK_CHECK(vkQueueSubmit(ctx_.queue(), 1, &si, fence_));
    VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    pi.waitSemaphoreCount = 1;
    pi.pWaitSemaphores = &rendered_[index];
    pi.swapchainCount = 1;
    VkSwapchainKHR sc = swapchain_->handle();
    pi.pSwapchains = &sc;
    pi.pImageIndices = &index;
    r = vkQueuePresentKHR(ctx_.presentQueue(), &pi);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) stale_ = true;
    else VK_CHECK(r);
    // One frame in flight: finish this one (its time belongs to this frame's figures).
    VK_CHECK(vkWaitForFences(d, 1, &fence_, VK_TRUE, UINT64_MAX));
    if (reading) {
        readback_.invalidate();
        size_t bytes = size_t(ext.width) * ext.height * 4;
        lastFrame_.resize(bytes);
        std::memcpy(lastFrame_.data(), readback_.mapped(), bytes);
        lastFrameExtent_ = ext;
    }
    return true;
}

}  // namespace metamer::preview
