#include "vk/device_objects.h"

#include <fmt/format.h>

#include <algorithm>

namespace metamer::vk {

DeviceObjects::DeviceObjects(VkDevice device, size_t capacity) : device_(device), capacity_(std::max<size_t>(1, capacity)) {}

DeviceObjects::~DeviceObjects() { clear(); }

void DeviceObjects::clear() {
    std::lock_guard<std::mutex> lock(mutex_);
    reusables_.clear();
    // Pipelines first: they hold their layouts and render passes.
    pipelines_ = {};
    pipelineLayouts_ = {};
    setLayouts_ = {};
    renderPasses_ = {};
}

template <typename Handle, typename Destroy>
SharedHandle<Handle> DeviceObjects::get(Kind<Handle>& kind, const std::string& key, const std::function<Handle()>& make,
                                        Destroy destroy, std::vector<std::shared_ptr<void>> uses) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = kind.objects.find(key);
    if (it != kind.objects.end()) {
        kind.recent.remove(key);
        kind.recent.push_front(key);
        ++reused_;
        return it->second;
    }
    const Handle h = make();
    VkDevice device = device_;
    SharedHandle<Handle> shared(h, [device, destroy, uses = std::move(uses)](Handle x) { destroy(device, x, nullptr); });
    kind.objects.emplace(key, shared);
    kind.recent.push_front(key);
    if (kind.recent.size() > capacity_) {
        kind.objects.erase(kind.recent.back());
        kind.recent.pop_back();
    }
    ++made_;
    return shared;
}

SharedHandle<VkRenderPass> DeviceObjects::renderPass(const std::string& key, const std::function<VkRenderPass()>& make) {
    return get(renderPasses_, key, make, vkDestroyRenderPass, {});
}

SharedHandle<VkDescriptorSetLayout> DeviceObjects::setLayout(const std::string& key,
                                                             const std::function<VkDescriptorSetLayout()>& make) {
    return get(setLayouts_, key, make, vkDestroyDescriptorSetLayout, {});
}

SharedHandle<VkPipelineLayout> DeviceObjects::pipelineLayout(const std::string& key,
                                                             const std::function<VkPipelineLayout()>& make,
                                                             std::vector<std::shared_ptr<void>> uses) {
    return get(pipelineLayouts_, key, make, vkDestroyPipelineLayout, std::move(uses));
}

SharedHandle<VkPipeline> DeviceObjects::pipeline(const std::string& key, const std::function<VkPipeline()>& make,
                                                 std::vector<std::shared_ptr<void>> uses) {
    return get(pipelines_, key, make, vkDestroyPipeline, std::move(uses));
}

std::shared_ptr<void> DeviceObjects::reusable(const std::string& key, const std::function<std::shared_ptr<void>()>& make,
                                              size_t keep) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto it = reusables_.begin(); it != reusables_.end(); ++it)
            if (it->first == key) {
                reusables_.splice(reusables_.begin(), reusables_, it);
                ++reused_;
                return it->second;
            }
    }
    std::shared_ptr<void> made = make();  // unlocked: making it may use this cache too (pipelines)
    std::lock_guard<std::mutex> lock(mutex_);
    ++made_;
    reusables_.emplace_front(key, made);
    while (reusables_.size() > keep) reusables_.pop_back();
    return made;
}

SharedHandle<VkRenderPass> DeviceObjects::renderPass(const std::string& key, const VkRenderPassCreateInfo& info) {
    return renderPass(key, [&] {
        VkRenderPass h = VK_NULL_HANDLE;
        VK_CHECK(vkCreateRenderPass(device_, &info, nullptr, &h));
        return h;
    });
}

SharedHandle<VkDescriptorSetLayout> DeviceObjects::setLayout(const std::string& key,
                                                             const VkDescriptorSetLayoutCreateInfo& info) {
    return setLayout(key, [&] {
        VkDescriptorSetLayout h = VK_NULL_HANDLE;
        VK_CHECK(vkCreateDescriptorSetLayout(device_, &info, nullptr, &h));
        return h;
    });
}

SharedHandle<VkPipelineLayout> DeviceObjects::pipelineLayout(const std::string& key, const VkPipelineLayoutCreateInfo& info,
                                                             std::vector<std::shared_ptr<void>> uses) {
    return pipelineLayout(
        key,
        [&] {
            VkPipelineLayout h = VK_NULL_HANDLE;
            VK_CHECK(vkCreatePipelineLayout(device_, &info, nullptr, &h));
            return h;
        },
        std::move(uses));
}

std::string keyBytes(const void* data, size_t size) {
    std::string s;
    const auto* b = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) s += fmt::format("{:02x}", b[i]);
    return s;
}

}  // namespace metamer::vk
