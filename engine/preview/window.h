// The preview's window: GLFW with no client API (Vulkan draws into it), its Vulkan surface and
// its input. No display (no DISPLAY, or GLFW cannot start) is Error(ExitCode::NoDisplay).
// Tests: tests/preview_test.sh.
#pragma once

#include <vulkan/vulkan.h>

#include <string>
#include <vector>

struct GLFWwindow;

namespace metamer::preview {

class Window {
public:
    // Opens a hidden width × height window (screen coordinates); show() maps it.
    Window(int width, int height, const std::string& title);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    GLFWwindow* handle() const { return window_; }
    // The instance extensions GLFW needs to make a surface (VK_KHR_surface and the platform's).
    std::vector<std::string> requiredInstanceExtensions() const;
    VkSurfaceKHR createSurface(VkInstance instance) const;

    void show();
    void resize(int width, int height);
    bool closeRequested() const;
    void requestClose();
    // Framebuffer size in pixels (what the swapchain must match); 0 × 0 while minimized.
    VkExtent2D framebufferSize() const;
    // Framebuffer pixels per screen coordinate (mouse positions are in screen coordinates).
    float pixelScale() const;
    void setTitle(const std::string& title);

    // Keys pressed since the last call (GLFW key codes), in order. Kept here because Dear ImGui
    // 1.86 reads key state once per frame and misses a press and release that fall within one.
    std::vector<int> takeKeyPresses();

private:
    static void onKey(GLFWwindow* window, int key, int scancode, int action, int mods);
    GLFWwindow* window_ = nullptr;
    std::vector<int> keys_;
};

}  // namespace metamer::preview
