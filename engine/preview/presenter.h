// One frame on the screen: the views' display images copied as bytes into the swapchain image at
// their places, the UI drawn over the rest, presented. One frame in flight (the frame waits for
// its own fence): lavapipe renders on the same CPU cores, so a second frame would only queue.
// Tests: tests/preview_test.sh (a window under Xvfb).
#pragma once

#include "preview/swapchain.h"
#include "preview/window.h"
#include "vk/resources.h"

#include <functional>
#include <memory>
#include <vector>

namespace metamer::preview {

// A display image to show: `pixels` holds width × height × 4 bytes in the swapchain's byte order
// (Swapchain::bgra()), row 0 at the top, placed with its top-left corner at (x, y) in framebuffer
// pixels. Parts outside the window are not shown.
struct ShownImage {
    int x = 0, y = 0, width = 0, height = 0;
    const std::vector<uint8_t>* pixels = nullptr;
};

class Presenter {
public:
    Presenter(vk::Context& ctx, const Window& window, bool immediate);
    ~Presenter();
    Presenter(const Presenter&) = delete;
    Presenter& operator=(const Presenter&) = delete;

    Swapchain& swapchain() { return *swapchain_; }

    // Copies the images into the upload buffer; every later frame shows them.
    void setImages(const std::vector<ShownImage>& images);

    // Draws and presents one frame, `ui` recording the UI into the swapchain's render pass. With
    // `readBack` (and Swapchain::readable()), the finished image is also copied to the host
    // (lastFrame()). Returns false when nothing was shown (the window is minimized or the
    // swapchain had to be made again): call again.
    bool frame(const std::function<void(VkCommandBuffer)>& ui, bool readBack);

    // The last read-back frame: extent.width × extent.height × 4 bytes, the swapchain's byte order.
    const std::vector<uint8_t>& lastFrame() const { return lastFrame_; }
    VkExtent2D lastFrameExtent() const { return lastFrameExtent_; }
    bool lastFrameRead() const { return !lastFrame_.empty(); }

private:
    void copyImages(VkCommandBuffer cmd, VkImage image) const;  // the display images into the swapchain image

    vk::Context& ctx_;
    const Window& window_;
    std::unique_ptr<Swapchain> swapchain_;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    VkSemaphore acquired_ = VK_NULL_HANDLE;
    std::vector<VkSemaphore> rendered_;  // per swapchain image: free again once it is re-acquired
    struct Region {
        int x, y, width, height;
        VkDeviceSize offset;
    };
    std::vector<Region> regions_;
    vk::Buffer upload_, readback_;
    std::vector<uint8_t> lastFrame_;
    VkExtent2D lastFrameExtent_{0, 0};
    bool stale_ = false;  // suboptimal or out of date: make the swapchain again before the next frame
};

}  // namespace metamer::preview
