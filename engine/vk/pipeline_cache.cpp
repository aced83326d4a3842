#include "vk/pipeline_cache.h"

#include "core/cache_folder.h"
#include "core/file_reads.h"

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <string_view>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace metamer::vk {

namespace {

// Vulkan's cache header (VkPipelineCacheHeaderVersionOne): length, version, vendor, device, UUID.
struct Header {
    uint32_t length, version, vendorID, deviceID;
    uint8_t uuid[VK_UUID_SIZE];
};
static_assert(sizeof(Header) == 16 + VK_UUID_SIZE);

// More than any pipeline cache Metamer makes (a few MiB): a file this large is not one of ours.
constexpr std::uintmax_t kMaxCacheBytes = std::uintmax_t(256) << 20;

std::string why(const std::vector<char>& data, const VkPhysicalDeviceProperties& p) {
    if (data.size() < sizeof(Header)) return "shorter than a cache header";
    Header h;
    std::memcpy(&h, data.data(), sizeof h);
    if (h.length < sizeof(Header) || h.version != VK_PIPELINE_CACHE_HEADER_VERSION_ONE) return "not a cache header";
    if (h.vendorID != p.vendorID || h.deviceID != p.deviceID) return "made on another device";
    if (std::memcmp(h.uuid, p.pipelineCacheUUID, VK_UUID_SIZE) != 0) return "made by another driver version";
    return "";
}

size_t hashOf(const std::vector<char>& data) { return std::hash<std::string_view>{}({data.data(), data.size()}); }

}  // namespace

fs::path pipelineCacheFolder() { return cacheFolder("METAMER_PIPELINE_CACHE"); }

PipelineCache::PipelineCache(VkDevice device, const VkPhysicalDeviceProperties& p, const fs::path& folder)
    : device_(device) {
    std::vector<char> data;
    if (!folder.empty()) {
        char uuid[2 * VK_UUID_SIZE + 1];
        for (int i = 0; i < int(VK_UUID_SIZE); ++i) std::snprintf(uuid + 2 * i, 3, "%02x", p.pipelineCacheUUID[i]);
        file_ = folder / fmt::format("pipelines-{:04x}-{:04x}-{}-{}.bin", p.vendorID, p.deviceID, p.driverVersion, uuid);
        // Only a regular file of a sane size is read: a FIFO there would block every render, a
        // device feed it for ever (the lobe cache's rule, core/file_reads.h).
        std::error_code ec;
        const fs::file_status status = fs::status(file_, ec);
        if (fs::exists(status) && !fs::is_regular_file(status)) {
            ignored_ = fmt::format("{}, not a regular file", specialFileKind(status));
        } else if (fs::exists(status) && fs::file_size(file_, ec) > kMaxCacheBytes) {
            ignored_ = fmt::format("over {} MiB", kMaxCacheBytes >> 20);
        } else if (std::ifstream in(file_, std::ios::binary); in) {
            data.assign(std::istreambuf_iterator<char>(in), {});
            ignored_ = why(data, p);
            if (!ignored_.empty()) data.clear();
        }
    }
    VkPipelineCacheCreateInfo ci{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
    ci.initialDataSize = data.size();
    ci.pInitialData = data.empty() ? nullptr : data.data();
    if (vkCreatePipelineCache(device, &ci, nullptr, &cache_) != VK_SUCCESS) {
        // The driver refused the data after all: start empty.
        ignored_ = "refused by the driver";
        ci.initialDataSize = 0;
        ci.pInitialData = nullptr;
        data.clear();
        VK_CHECK(vkCreatePipelineCache(device, &ci, nullptr, &cache_));
    }
    loaded_ = data.size();
    loadedHash_ = data.empty() ? 0 : hashOf(data);
}

PipelineCache::~PipelineCache() {
    try {
        save();
    } catch (...) {
    }
    if (cache_) vkDestroyPipelineCache(device_, cache_, nullptr);
}

bool PipelineCache::save() {
    if (file_.empty() || !cache_) return true;
    size_t size = 0;
    if (vkGetPipelineCacheData(device_, cache_, &size, nullptr) != VK_SUCCESS || size == 0) return false;
    std::vector<char> data(size);
    if (vkGetPipelineCacheData(device_, cache_, &size, data.data()) != VK_SUCCESS) return false;
    data.resize(size);
    if (loaded_ == data.size() && hashOf(data) == loadedHash_) return true;  // nothing new
    std::error_code ec;
    fs::create_directories(file_.parent_path(), ec);
    const fs::path temp = file_.parent_path() / fmt::format(".{}.tmp-{}", file_.filename().string(), ::getpid());
    {
        std::ofstream out(temp, std::ios::binary);
        out.write(data.data(), std::streamsize(data.size()));
        if (!out) {
            fs::remove(temp, ec);
            return false;
        }
    }
    fs::rename(temp, file_, ec);
    if (ec) {
        fs::remove(temp, ec);
        return false;
    }
    loaded_ = data.size();
    loadedHash_ = hashOf(data);
    return true;
}

}  // namespace metamer::vk
