// Owned Vulkan handles: a handle with the device and the function that destroys it, destroyed
// once, by the owner's destructor (move-only). So a pass holds Owned<VkPipeline> members instead
// of raw handles and a hand-written destructor that must list every one of them.
// Tests: through the GPU tests, with validation layers on (tests/support/gpu.h).
#pragma once

#include <vulkan/vulkan.h>

#include <utility>

namespace metamer::vk {

template <typename T>
using Destroyer = void (*)(VkDevice, T, const VkAllocationCallbacks*);

template <typename T, Destroyer<T> destroy>
class Owned {
public:
    Owned() = default;
    Owned(VkDevice device, T handle) : device_(device), handle_(handle) {}
    ~Owned() { reset(); }
    Owned(const Owned&) = delete;
    Owned& operator=(const Owned&) = delete;
    Owned(Owned&& o) noexcept : device_(o.device_), handle_(std::exchange(o.handle_, T(VK_NULL_HANDLE))) {}
    Owned& operator=(Owned&& o) noexcept {
        if (this != &o) {
            reset();
            device_ = o.device_;
            handle_ = std::exchange(o.handle_, T(VK_NULL_HANDLE));
        }
        return *this;
    }

    T get() const { return handle_; }
    // For a vkCreate* call: frees what is held, then the slot the call writes into.
    T* put(VkDevice device) {
        reset();
        device_ = device;
        return &handle_;
    }
    explicit operator bool() const { return handle_ != T(VK_NULL_HANDLE); }
    void reset() {
        if (handle_ != T(VK_NULL_HANDLE)) destroy(device_, handle_, nullptr);
        handle_ = T(VK_NULL_HANDLE);
    }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    T handle_ = T(VK_NULL_HANDLE);
};

using OwnedRenderPass = Owned<VkRenderPass, vkDestroyRenderPass>;
using OwnedPipeline = Owned<VkPipeline, vkDestroyPipeline>;
using OwnedPipelineLayout = Owned<VkPipelineLayout, vkDestroyPipelineLayout>;
using OwnedFramebuffer = Owned<VkFramebuffer, vkDestroyFramebuffer>;
using OwnedShaderModule = Owned<VkShaderModule, vkDestroyShaderModule>;
using OwnedDescriptorSetLayout = Owned<VkDescriptorSetLayout, vkDestroyDescriptorSetLayout>;
using OwnedDescriptorPool = Owned<VkDescriptorPool, vkDestroyDescriptorPool>;
using OwnedSampler = Owned<VkSampler, vkDestroySampler>;
using OwnedBufferView = Owned<VkBufferView, vkDestroyBufferView>;

}  // namespace metamer::vk
