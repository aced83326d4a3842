#include "preview/swapchain.h"
#include "vk/render_pass.h"

#include <algorithm>

namespace metamer::preview {

Swapchain::Swapchain(vk::Context& ctx, VkExtent2D size, bool immediate) : ctx_(ctx), immediate_(immediate) {
    VkPhysicalDevice pd = ctx.physicalDevice();
    VkSurfaceKHR surface = ctx.surface();
    uint32_t n = 0;
    VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, nullptr));
    std::vector<VkSurfaceFormatKHR> formats(n);
    VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, formats.data()));
    // 8-bit formats only: the counts are copied in as bytes. UNORM first (the UI's colours are
    // then as written); an SRGB format shows the same counts, since a copy does not convert.
    const VkFormat wanted[4] = {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_SRGB,
                                VK_FORMAT_R8G8B8A8_SRGB};
    for (VkFormat w : wanted) {
        auto it = std::find_if(formats.begin(), formats.end(), [&](const VkSurfaceFormatKHR& f) { return f.format == w; });
        if (it != formats.end()) {
            format_ = it->format;
            colorSpace_ = it->colorSpace;
            break;
        }
    }
    if (format_ == VK_FORMAT_UNDEFINED)
        failRuntime("the window offers no 8-bit BGRA or RGBA swapchain format ({} formats offered)", n);

    VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, nullptr));
    std::vector<VkPresentModeKHR> modes(n);
    VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, modes.data()));
    presentMode_ = VK_PRESENT_MODE_FIFO_KHR;
    if (immediate_)
        for (VkPresentModeKHR m : {VK_PRESENT_MODE_IMMEDIATE_KHR, VK_PRESENT_MODE_MAILBOX_KHR})
            if (std::find(modes.begin(), modes.end(), m) != modes.end()) {
                presentMode_ = m;
                break;
            }

    // The UI pass draws over the images the frame has already copied in (load, not clear); the
    // present frame's derived barriers (preview/presenter.cpp) bring the image in and out.
    vk::RenderPassDesc desc;
    desc.colors.push_back(vk::attachmentFor(format_, vk::Access::ColorAttachment, VK_ATTACHMENT_LOAD_OP_LOAD));
    renderPass_ = vk::createRenderPass(ctx.device(), desc);
    try {
        create(size, VK_NULL_HANDLE);
    } catch (...) {
        vkDestroyRenderPass(ctx.device(), renderPass_, nullptr);
        throw;
    }
}

Swapchain::~Swapchain() {
    vkDeviceWaitIdle(ctx_.device());
    destroyImages();
    if (swapchain_) vkDestroySwapchainKHR(ctx_.device(), swapchain_, nullptr);
    if (renderPass_) vkDestroyRenderPass(ctx_.device(), renderPass_, nullptr);
}

const char* Swapchain::presentModeName() const {
    switch (presentMode_) {
        case VK_PRESENT_MODE_IMMEDIATE_KHR: return "immediate";
        case VK_PRESENT_MODE_MAILBOX_KHR: return "mailbox";
        case VK_PRESENT_MODE_FIFO_KHR: return "fifo";
        case VK_PRESENT_MODE_FIFO_RELAXED_KHR: return "fifo-relaxed";
        default: return "other";
    }
}

void Swapchain::destroyImages() {
    VkDevice d = ctx_.device();
    for (VkFramebuffer f : framebuffers_) vkDestroyFramebuffer(d, f, nullptr);
    for (VkImageView v : views_) vkDestroyImageView(d, v, nullptr);
    framebuffers_.clear();
    views_.clear();
    images_.clear();
}

void Swapchain::recreate(VkExtent2D size) {
    vkDeviceWaitIdle(ctx_.device());
    destroyImages();
    VkSwapchainKHR old = swapchain_;
    swapchain_ = VK_NULL_HANDLE;
    try {
        create(size, old);
    } catch (...) {
        vkDestroySwapchainKHR(ctx_.device(), old, nullptr);
        throw;
    }
    vkDestroySwapchainKHR(ctx_.device(), old, nullptr);
}

void Swapchain::create(VkExtent2D size, VkSwapchainKHR old) {
    VkDevice d = ctx_.device();
    VkSurfaceCapabilitiesKHR caps;
    VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx_.physicalDevice(), ctx_.surface(), &caps));
    if (caps.currentExtent.width != 0xFFFFFFFFu) {
        extent_ = caps.currentExtent;
    } else {
        extent_.width = std::clamp(size.width, caps.minImageExtent.width, caps.maxImageExtent.width);
        extent_.height = std::clamp(size.height, caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    uint32_t count = std::max(2u, caps.minImageCount + 1);
    if (caps.maxImageCount) count = std::min(count, caps.maxImageCount);
    minImageCount_ = std::max(2u, caps.minImageCount);
    // Copies in (the display image), colour attachment (the UI), copies out (screenshots) when allowed.
    VkImageUsageFlags usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
        failRuntime("the window's swapchain images cannot be copied into (no TRANSFER_DST usage)");
    readable_ = caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    if (readable_) usage |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    VkCompositeAlphaFlagBitsKHR alpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    for (VkCompositeAlphaFlagBitsKHR a : {VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR, VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR,
                                          VK_COMPOSITE_ALPHA_PRE_MULTIPLIED_BIT_KHR,
                                          VK_COMPOSITE_ALPHA_POST_MULTIPLIED_BIT_KHR})
        if (caps.supportedCompositeAlpha & a) {
            alpha = a;
            break;
        }

    VkSwapchainCreateInfoKHR ci{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    ci.surface = ctx_.surface();
    ci.minImageCount = count;
    ci.imageFormat = format_;
    ci.imageColorSpace = colorSpace_;
    ci.imageExtent = extent_;
    ci.imageArrayLayers = 1;
    ci.imageUsage = usage;
    uint32_t families[2] = {ctx_.queueFamily(), ctx_.presentFamily()};
    if (families[0] != families[1]) {
        ci.imageSharingMode = VK_SHARING_MODE_CONCURRENT;
        ci.queueFamilyIndexCount = 2;
        ci.pQueueFamilyIndices = families;
    } else {
        ci.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    }
    ci.preTransform = (caps.supportedTransforms & VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR)
                          ? VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR
                          : caps.currentTransform;
    ci.compositeAlpha = alpha;
    ci.presentMode = presentMode_;
    ci.clipped = VK_FALSE;  // every pixel is defined: screenshots read them back
    ci.oldSwapchain = old;
    VK_CHECK(vkCreateSwapchainKHR(d, &ci, nullptr, &swapchain_));

    uint32_t n = 0;
    VK_CHECK(vkGetSwapchainImagesKHR(d, swapchain_, &n, nullptr));
    images_.resize(n);
    VK_CHECK(vkGetSwapchainImagesKHR(d, swapchain_, &n, images_.data()));
    for (VkImage image : images_) {
        VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        vi.image = image;
        vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
        vi.format = format_;
        vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VkImageView view;
        VK_CHECK(vkCreateImageView(d, &vi, nullptr, &view));
        views_.push_back(view);
        VkFramebufferCreateInfo fb{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
        fb.renderPass = renderPass_;
        fb.attachmentCount = 1;
        fb.pAttachments = &view;
        fb.width = extent_.width;
        fb.height = extent_.height;
        fb.layers = 1;
        VkFramebuffer f;
        VK_CHECK(vkCreateFramebuffer(d, &fb, nullptr, &f));
        framebuffers_.push_back(f);
    }
}

}  // namespace metamer::preview
