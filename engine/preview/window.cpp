#include "preview/window.h"

#include "core/error.h"

#define GLFW_INCLUDE_NONE
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdlib>

namespace metamer::preview {

namespace {

std::string gLastGlfwError;

void onGlfwError(int code, const char* text) { gLastGlfwError = fmt::format("{} (GLFW error {:#x})", text, code); }

}  // namespace

Window::Window(int width, int height, const std::string& title) {
    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit()) {
        const char* display = std::getenv("DISPLAY");
        const char* wayland = std::getenv("WAYLAND_DISPLAY");
        std::string why = gLastGlfwError.empty() ? "glfwInit failed" : gLastGlfwError;
        if ((!display || !*display) && (!wayland || !*wayland))
            why = "DISPLAY is not set; run it in a desktop session, or under Xvfb (xvfb-run -a metamer preview ...)";
        throw Error(ExitCode::NoDisplay, Where{}, "no display to open the preview window on: " + why);
    }
    if (!glfwVulkanSupported()) {
        glfwTerminate();
        throw Error(ExitCode::NoDevice, Where{},
                    "no usable Vulkan device: GLFW finds no Vulkan loader or no surface extension for this "
                    "display (install libvulkan1 and mesa-vulkan-drivers)" +
                        (gLastGlfwError.empty() ? std::string() : ": " + gLastGlfwError));
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window_) {
        std::string why = gLastGlfwError;
        glfwTerminate();
        throw Error(ExitCode::NoDisplay, Where{}, "the preview window could not be created: " + why);
    }
    // Installed before Dear ImGui's, which calls it after its own.
    glfwSetWindowUserPointer(window_, this);
    glfwSetKeyCallback(window_, onKey);
}

void Window::onKey(GLFWwindow* window, int key, int, int action, int) {
    auto* self = static_cast<Window*>(glfwGetWindowUserPointer(window));
    if (self && action == GLFW_PRESS) self->keys_.push_back(key);
}

std::vector<int> Window::takeKeyPresses() {
    std::vector<int> keys;
    keys.swap(keys_);
    return keys;
}

Window::~Window() {
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
}

std::vector<std::string> Window::requiredInstanceExtensions() const {
    uint32_t n = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&n);
    if (!names)
        throw Error(ExitCode::NoDevice, Where{},
                    "no usable Vulkan device: the Vulkan loader offers no surface extension for this display (" +
                        gLastGlfwError + ")");
    return std::vector<std::string>(names, names + n);
}

VkSurfaceKHR Window::createSurface(VkInstance instance) const {
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    VkResult r = glfwCreateWindowSurface(instance, window_, nullptr, &surface);
    if (r != VK_SUCCESS) failRuntime("the preview window's Vulkan surface could not be created: {}", gLastGlfwError);
    return surface;
}

void Window::show() { glfwShowWindow(window_); }

void Window::resize(int width, int height) { glfwSetWindowSize(window_, width, height); }

bool Window::closeRequested() const { return glfwWindowShouldClose(window_); }

void Window::requestClose() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }

VkExtent2D Window::framebufferSize() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    return {uint32_t(std::max(w, 0)), uint32_t(std::max(h, 0))};
}

float Window::pixelScale() const {
    int w = 0, h = 0, fw = 0, fh = 0;
    glfwGetWindowSize(window_, &w, &h);
    glfwGetFramebufferSize(window_, &fw, &fh);
    return w > 0 ? float(fw) / float(w) : 1.0f;
}

void Window::setTitle(const std::string& title) { glfwSetWindowTitle(window_, title.c_str()); }

}  // namespace metamer::preview
