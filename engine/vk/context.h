// The Vulkan instance and device: headless by default (no window-system extensions), or able to
// present to a window's surface when ContextOptions asks for it (the preview, engine/preview).
// The device: --device / METAMER_DEVICE, CUDA_VISIBLE_DEVICES, SLURM_LOCALID, else the best score
// (vk/device_choice.h). lavapipe's LP_NUM_THREADS comes from core/cpu_count unless the user set it.
// With validation on, every validation error is counted (and printed); tests require zero,
// including the leak reports the layers make when the device is destroyed.
// Tests: tests/cli_test.cpp (device choice, no device), the GPU tests.
#pragma once

#include "vk/check.h"
#include "vk/device_choice.h"

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace metamer::vk {

class PipelineCache;
class DeviceObjects;

struct ContextOptions {
    // Enable VK_LAYER_KHRONOS_validation. Default: on when METAMER_VALIDATION=1.
    bool validation = false;
    // Device choice (vk/device_choice.h): "" = what the scheduler's variables say, else the best
    // score; else an index into the device list, a UUID or a name substring. Default: $METAMER_DEVICE.
    std::string device;
    std::string deviceFrom = "METAMER_DEVICE";  // "--device" when the flag set `device`, for messages
    // The scheduler's binding (default: from the environment; empty: unset).
    std::string cudaVisibleDevices, slurmLocalId;
    bool verbose = false;  // print the chosen device

    // Presentation (empty: headless). The window system's instance extensions (e.g. from
    // glfwGetRequiredInstanceExtensions), and a function that makes the window's surface once the
    // instance exists. The device is then chosen among those that can present to that surface and
    // have VK_KHR_swapchain (enabled), and the Context owns the surface (destroyed before the
    // instance).
    std::vector<std::string> instanceExtensions;
    std::function<VkSurfaceKHR(VkInstance)> createSurface;

    // Where the pipeline cache is kept between processes (vk/pipeline_cache.h); empty: in memory
    // only. Default from the environment: METAMER_PIPELINE_CACHE, $XDG_CACHE_HOME/metamer, ~/.cache/metamer.
    std::filesystem::path pipelineCacheFolder;
};

ContextOptions contextOptionsFromEnvironment();

class Context {
public:
    // Throws Error(ExitCode::NoDevice) when there is no Vulkan driver or no usable device.
    explicit Context(const ContextOptions& options = contextOptionsFromEnvironment());
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    VkInstance instance() const { return instance_; }
    VkPhysicalDevice physicalDevice() const { return physical_; }
    VkDevice device() const { return device_; }
    VkQueue queue() const { return queue_; }
    uint32_t queueFamily() const { return queueFamily_; }
    VkCommandPool commandPool() const { return commandPool_; }
    // With a surface (ContextOptions::createSurface): the surface, and a queue that presents to it
    // (the graphics queue itself when its family can present, as on every driver seen so far).
    VkSurfaceKHR surface() const { return surface_; }
    VkQueue presentQueue() const { return presentQueue_; }
    uint32_t presentFamily() const { return presentFamily_; }
    const VkPhysicalDeviceProperties& properties() const { return properties_; }
    const VkPhysicalDeviceMemoryProperties& memoryProperties() const { return memory_; }
    const DeviceInfo& deviceInfo() const { return info_; }
    const std::string& deviceReason() const { return deviceReason_; }  // why this device ("the best score")
    bool validationEnabled() const { return validation_; }
    // The pipeline cache every pipeline is made with (kept on disk: vk/pipeline_cache.h).
    VkPipelineCache pipelineCache() const;
    const PipelineCache& pipelineCacheFile() const { return *pipelineCache_; }
    // Render passes, layouts and pipelines shared by every pass made with this context
    // (vk/device_objects.h).
    DeviceObjects& objects() { return *objects_; }

    // Validation errors reported so far (the count includes leak reports at destruction, which
    // the owner can only observe through validationErrorsAtExit()).
    uint32_t validationErrors() const { return validationErrors_.load(); }
    static uint32_t validationErrorsAtExit();  // summed over destroyed contexts

    // A memory type index with all `required` flags (and `preferred` ones if possible).
    uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required,
                            VkMemoryPropertyFlags preferred = 0) const;

    // Record into a one-time command buffer, submit, wait.
    template <typename F>
    void submitAndWait(F&& record);

    // Debug name on any object (no-op without validation).
    void setName(VkObjectType type, uint64_t handle, const char* name) const;

    // With a surface, a device that cannot present to it (or lacks VK_KHR_swapchain) scores 0.
    static std::vector<DeviceInfo> listDevices(VkInstance instance, VkSurfaceKHR surface = VK_NULL_HANDLE);

    // Sets LP_NUM_THREADS (lavapipe's rasterizer threads) to core/cpu_count's count unless it is set
    // already; lavapipe reads it when the instance is made, so every vkCreateInstance comes after.
    // Returns "LP_NUM_THREADS=N" and who set it, for -v.
    static std::string sizeDriverThreads();

private:
    void release();
    VkCommandBuffer beginOneTime();
    void endOneTimeAndWait(VkCommandBuffer cmd);
    static VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(
        VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
        const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);

    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    uint32_t queueFamily_ = 0;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    VkQueue presentQueue_ = VK_NULL_HANDLE;
    uint32_t presentFamily_ = 0;
    VkCommandPool commandPool_ = VK_NULL_HANDLE;
    std::unique_ptr<PipelineCache> pipelineCache_;
    std::unique_ptr<DeviceObjects> objects_;
    VkPhysicalDeviceProperties properties_{};
    VkPhysicalDeviceMemoryProperties memory_{};
    DeviceInfo info_;
    std::string deviceReason_;
    bool validation_ = false;
    std::atomic<uint32_t> validationErrors_{0};
    PFN_vkSetDebugUtilsObjectNameEXT setObjectName_ = nullptr;
};

template <typename F>
void Context::submitAndWait(F&& record) {
    VkCommandBuffer cmd = beginOneTime();
    record(cmd);
    endOneTimeAndWait(cmd);
}

}  // namespace metamer::vk
