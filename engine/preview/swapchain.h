// The window's swapchain: its images, their views and the framebuffers of the UI render pass.
// Images are 8-bit BGRA or RGBA (UNORM or SRGB): the display counts are copied into them as bytes
// (presenter.h), so the window shows exactly the counts `metamer render` writes to its PNG.
// Tests: tests/preview_test.sh.
#pragma once

#include "vk/context.h"

#include <vector>

namespace metamer::preview {

class Swapchain {
public:
    // `immediate`: prefer a present mode that does not wait for vertical blank (IMMEDIATE, then
    // MAILBOX), for frame-time measurements; otherwise FIFO (always available).
    Swapchain(vk::Context& ctx, VkExtent2D size, bool immediate);
    ~Swapchain();
    Swapchain(const Swapchain&) = delete;
    Swapchain& operator=(const Swapchain&) = delete;

    // Makes the swapchain again for a new window size (waits for the device to be idle).
    void recreate(VkExtent2D size);

    VkSwapchainKHR handle() const { return swapchain_; }
    VkFormat format() const { return format_; }
    bool bgra() const { return format_ == VK_FORMAT_B8G8R8A8_UNORM || format_ == VK_FORMAT_B8G8R8A8_SRGB; }
    VkExtent2D extent() const { return extent_; }
    uint32_t imageCount() const { return uint32_t(images_.size()); }
    uint32_t minImageCount() const { return minImageCount_; }
    VkImage image(uint32_t i) const { return images_[i]; }
    VkFramebuffer framebuffer(uint32_t i) const { return framebuffers_[i]; }
    VkRenderPass renderPass() const { return renderPass_; }
    VkPresentModeKHR presentMode() const { return presentMode_; }
    bool readable() const { return readable_; }  // images can be copied from (screenshots)
    const char* presentModeName() const;

private:
    void create(VkExtent2D size, VkSwapchainKHR old);
    void destroyImages();

    vk::Context& ctx_;
    bool immediate_;
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    VkColorSpaceKHR colorSpace_ = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
    VkExtent2D extent_{0, 0};
    VkPresentModeKHR presentMode_ = VK_PRESENT_MODE_FIFO_KHR;
    uint32_t minImageCount_ = 2;
    bool readable_ = false;
    VkRenderPass renderPass_ = VK_NULL_HANDLE;
    std::vector<VkImage> images_;
    std::vector<VkImageView> views_;
    std::vector<VkFramebuffer> framebuffers_;
};

}  // namespace metamer::preview
