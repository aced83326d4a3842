// Vulkan's pipeline cache, kept on disk between processes: one file per device and driver
// (pipelines-<vendor>-<device>-<driver version>-<cache UUID>.bin) in the folder
// METAMER_PIPELINE_CACHE names ("off": none), else $XDG_CACHE_HOME/metamer, else
// ~/.cache/metamer. Read when a Context is made; written back (a temporary file renamed over the
// old one, so concurrent processes never see half a file) when the Context is destroyed, if the
// driver's data changed. A file whose header is not this device's and driver's (stale, truncated,
// foreign) is ignored and replaced. What it saves depends on the driver: lavapipe (Mesa 22.3)
// keeps no compiled code in it (docs/performance.md, "Start-up").
// Tests: engine/vk/pipeline_cache_test.cpp.
#pragma once

#include "vk/check.h"

#include <filesystem>
#include <string>

namespace metamer::vk {

// The folder from the environment as above; empty when disabled or when there is no home.
std::filesystem::path pipelineCacheFolder();

class PipelineCache {
public:
    // `folder` empty: an in-memory cache only (nothing read or written).
    PipelineCache(VkDevice device, const VkPhysicalDeviceProperties& properties, const std::filesystem::path& folder);
    ~PipelineCache();  // save() then destroy; never throws
    PipelineCache(const PipelineCache&) = delete;
    PipelineCache& operator=(const PipelineCache&) = delete;

    VkPipelineCache handle() const { return cache_; }
    const std::filesystem::path& file() const { return file_; }  // empty: not on disk
    size_t loadedBytes() const { return loaded_; }  // the driver's data taken from the file (0: none or ignored)
    std::string ignoredBecause() const { return ignored_; }  // why a file was not used, or ""

    // Writes the driver's current data if it differs from what was loaded; false on a write error
    // (the cache is an optimization: a failure to save is not a failure of the render).
    bool save();

private:
    VkDevice device_;
    VkPipelineCache cache_ = VK_NULL_HANDLE;
    std::filesystem::path file_;
    size_t loaded_ = 0, loadedHash_ = 0;
    std::string ignored_;
};

}  // namespace metamer::vk
