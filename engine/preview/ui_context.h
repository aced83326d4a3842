// Dear ImGui on the preview's window: the context, the GLFW platform backend (input) and the
// Vulkan renderer backend (drawing into the swapchain's render pass), from Debian's libimgui-dev.
//
// Debian's Dear ImGui is 1.86, whose Vulkan backend cannot draw user textures (every draw binds
// the font atlas). The display images are therefore not ImGui images: the presenter copies them
// into the swapchain image as bytes and ImGui draws its panels over the rest (presenter.h).
// Tests: tests/preview_test.sh.
#pragma once

#include "preview/swapchain.h"
#include "preview/window.h"
#include "vk/context.h"

namespace metamer::preview {

class UiContext {
public:
    UiContext(vk::Context& ctx, const Window& window, Swapchain& swapchain);
    ~UiContext();
    UiContext(const UiContext&) = delete;
    UiContext& operator=(const UiContext&) = delete;

    // Starts an ImGui frame (reads the input GLFW gathered).
    void newFrame();
    // Ends the frame (its draw lists are final).
    void endFrame();
    // Records the ended frame's draw lists into `cmd`, inside the swapchain's render pass.
    void record(VkCommandBuffer cmd);

private:
    vk::Context& ctx_;
    Swapchain& swapchain_;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
    uint32_t imageCount_ = 0;
};

}  // namespace metamer::preview
