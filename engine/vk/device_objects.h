// Device objects that passes make again and again from the same description — render passes,
// descriptor set layouts, pipeline layouts, pipelines — made once per Context under a key that
// names everything they depend on, and shared. A batch's jobs, a preview view rebuilt after a
// light change, the suite's tests: each new pass of a configuration seen before then skips the
// driver's pipeline compilation (on lavapipe, 40 % of a small job's time). A handle lives while a
// pass holds it or the cache keeps it (the most recently used `capacity` of each kind); a pipeline
// holds its layout and render pass, so they outlive it. Tests: engine/vk/device_objects_test.cpp.
#pragma once

#include "vk/check.h"

#include <functional>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <type_traits>
#include <vector>

namespace metamer::vk {

template <typename Handle>
using SharedHandle = std::shared_ptr<std::remove_pointer_t<Handle>>;

class DeviceObjects {
public:
    explicit DeviceObjects(VkDevice device, size_t capacity = 64);
    ~DeviceObjects();
    DeviceObjects(const DeviceObjects&) = delete;
    DeviceObjects& operator=(const DeviceObjects&) = delete;

    // The object under `key`, made by `make` (which returns a new handle) the first time.
    SharedHandle<VkRenderPass> renderPass(const std::string& key, const std::function<VkRenderPass()>& make);
    SharedHandle<VkDescriptorSetLayout> setLayout(const std::string& key,
                                                  const std::function<VkDescriptorSetLayout()>& make);
    SharedHandle<VkPipelineLayout> pipelineLayout(const std::string& key, const std::function<VkPipelineLayout()>& make,
                                                  std::vector<std::shared_ptr<void>> uses);
    // The same, made from a create-info (the usual caller: `info` describes what the key names).
    SharedHandle<VkRenderPass> renderPass(const std::string& key, const VkRenderPassCreateInfo& info);
    SharedHandle<VkDescriptorSetLayout> setLayout(const std::string& key, const VkDescriptorSetLayoutCreateInfo& info);
    SharedHandle<VkPipelineLayout> pipelineLayout(const std::string& key, const VkPipelineLayoutCreateInfo& info,
                                                  std::vector<std::shared_ptr<void>> uses);
    // `uses`: what the pipeline was made with (its layout, render pass), kept alive as long as it is.
    SharedHandle<VkPipeline> pipeline(const std::string& key, const std::function<VkPipeline()>& make,
                                      std::vector<std::shared_ptr<void>> uses);

    // What an earlier render on this device made that a later one may reuse as it is (a scene's
    // shadow maps: drawn from the geometry and the lights, not the camera): under a key that holds
    // everything it was made from, byte for byte, so a hit is never a near miss. The `keep` most
    // recently used are kept (they may be large); a holder keeps its own alive.
    std::shared_ptr<void> reusable(const std::string& key, const std::function<std::shared_ptr<void>()>& make, size_t keep);

    size_t made() const { return made_; }
    size_t reused() const { return reused_; }
    // Lets go of every cached handle (those still held by passes stay alive with them).
    void clear();

private:
    template <typename Handle>
    struct Kind {
        std::map<std::string, SharedHandle<Handle>> objects;
        std::list<std::string> recent;  // most recently used first
    };
    template <typename Handle, typename Destroy>
    SharedHandle<Handle> get(Kind<Handle>& kind, const std::string& key, const std::function<Handle()>& make,
                             Destroy destroy, std::vector<std::shared_ptr<void>> uses);

    VkDevice device_;
    size_t capacity_;
    std::mutex mutex_;
    Kind<VkRenderPass> renderPasses_;
    Kind<VkDescriptorSetLayout> setLayouts_;
    Kind<VkPipelineLayout> pipelineLayouts_;
    Kind<VkPipeline> pipelines_;
    std::list<std::pair<std::string, std::shared_ptr<void>>> reusables_;  // most recently used first
    size_t made_ = 0, reused_ = 0;
};

// The bytes of a specialization-constant block as hex, for keys.
std::string keyBytes(const void* data, size_t size);

}  // namespace metamer::vk
