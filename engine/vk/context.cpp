#include "vk/context.h"

#include "core/cpu_count.h"
#include "vk/device_objects.h"
#include "vk/pipeline_cache.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace metamer::vk {

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
std::atomic<uint32_t> gValidationErrorsAtExit{0};

[[noreturn]] void failNoDevice(const std::string& why) {
    throw Error(ExitCode::NoDevice, Where{}, "no usable Vulkan device: " + why);
}

int scoreType(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 400;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 300;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 200;
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return 100;
        default: return 50;
    }
}

bool hasLayer(const char* name) {
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> layers(n);
    vkEnumerateInstanceLayerProperties(&n, layers.data());
    return std::any_of(layers.begin(), layers.end(),
                       [&](const VkLayerProperties& l) { return std::strcmp(l.layerName, name) == 0; });
}

bool hasDeviceExtension(VkPhysicalDevice pd, const char* name) {
    uint32_t n = 0;
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> ext(n);
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, ext.data());
    return std::any_of(ext.begin(), ext.end(),
                       [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
}

// A device we can render with: a graphics queue and RGBA32F + D32 render targets; with a surface,
// also VK_KHR_swapchain and a queue family that presents to it (the graphics family preferred).
bool usable(VkPhysicalDevice pd, uint32_t* family, VkSurfaceKHR surface = VK_NULL_HANDLE,
            uint32_t* presentFamily = nullptr) {
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
    std::vector<VkQueueFamilyProperties> families(n);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, families.data());
    auto presents = [&](uint32_t i) {
        VkBool32 ok = VK_FALSE;
        return vkGetPhysicalDeviceSurfaceSupportKHR(pd, i, surface, &ok) == VK_SUCCESS && ok;
    };
    bool found = false;
    for (uint32_t i = 0; i < n && !found; ++i)
        if (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) {
            *family = i;
            found = true;
        }
    if (!found) return false;
    if (surface) {
        if (!hasDeviceExtension(pd, VK_KHR_SWAPCHAIN_EXTENSION_NAME)) return false;
        // A graphics family that also presents, else the first that presents.
        bool both = false;
        for (uint32_t i = 0; i < n && !both; ++i)
            if ((families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) && presents(i)) {
                *family = i;
                if (presentFamily) *presentFamily = i;
                both = true;
            }
        if (!both) {
            bool any = false;
            for (uint32_t i = 0; i < n && !any; ++i)
                if (presents(i)) {
                    if (presentFamily) *presentFamily = i;
                    any = true;
                }
            if (!any) return false;
        }
    } else if (presentFamily) {
        *presentFamily = *family;
    }
    VkFormatProperties color{}, depth{};
    vkGetPhysicalDeviceFormatProperties(pd, VK_FORMAT_R32G32B32A32_SFLOAT, &color);
    vkGetPhysicalDeviceFormatProperties(pd, VK_FORMAT_D32_SFLOAT, &depth);
    return (color.optimalTilingFeatures & VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT) &&
           (depth.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT);
}


}  // namespace

const char* resultName(VkResult r) {
    switch (r) {
#define NAME(x) \
    case x: return #x;
        NAME(VK_SUCCESS) NAME(VK_NOT_READY) NAME(VK_TIMEOUT) NAME(VK_INCOMPLETE)
        NAME(VK_ERROR_OUT_OF_HOST_MEMORY) NAME(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        NAME(VK_ERROR_INITIALIZATION_FAILED) NAME(VK_ERROR_DEVICE_LOST)
        NAME(VK_ERROR_MEMORY_MAP_FAILED) NAME(VK_ERROR_LAYER_NOT_PRESENT)
        NAME(VK_ERROR_EXTENSION_NOT_PRESENT) NAME(VK_ERROR_FEATURE_NOT_PRESENT)
        NAME(VK_ERROR_INCOMPATIBLE_DRIVER) NAME(VK_ERROR_TOO_MANY_OBJECTS)
        NAME(VK_ERROR_FORMAT_NOT_SUPPORTED) NAME(VK_ERROR_FRAGMENTED_POOL)
        NAME(VK_ERROR_OUT_OF_DATE_KHR) NAME(VK_SUBOPTIMAL_KHR) NAME(VK_ERROR_SURFACE_LOST_KHR)
#undef NAME
        default: return "VkResult(other)";
    }
}

ContextOptions contextOptionsFromEnvironment() {
    ContextOptions o;
    if (const char* v = std::getenv("METAMER_VALIDATION")) o.validation = std::strcmp(v, "0") != 0;
    const DeviceRequest request = deviceRequestFromEnvironment();
    o.device = request.device;
    o.cudaVisibleDevices = request.cudaVisibleDevices;
    o.slurmLocalId = request.slurmLocalId;
    o.pipelineCacheFolder = pipelineCacheFolder();
    return o;
}

std::vector<DeviceInfo> Context::listDevices(VkInstance instance, VkSurfaceKHR surface) {
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(instance, &n, nullptr);
    std::vector<VkPhysicalDevice> pds(n);
    vkEnumeratePhysicalDevices(instance, &n, pds.data());
    std::vector<DeviceInfo> out;
    for (uint32_t i = 0; i < n; ++i) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(pds[i], &p);
        uint32_t family;
        DeviceInfo d{i, p.deviceName, p.deviceType, usable(pds[i], &family, surface) ? scoreType(p.deviceType) : 0, ""};
        if (VK_API_VERSION_MINOR(p.apiVersion) >= 1 || VK_API_VERSION_MAJOR(p.apiVersion) > 1) {
            VkPhysicalDeviceIDProperties id{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ID_PROPERTIES};
            VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
            p2.pNext = &id;
            vkGetPhysicalDeviceProperties2(pds[i], &p2);
            // 8-4-4-4-12 hex, as nvidia-smi -L and CUDA_VISIBLE_DEVICES write it (after "GPU-").
            for (int b = 0; b < int(VK_UUID_SIZE); ++b)
                d.uuid += fmt::format("{}{:02x}", b == 4 || b == 6 || b == 8 || b == 10 ? "-" : "", id.deviceUUID[b]);
        }
        out.push_back(d);
    }
    return out;
}

std::string Context::sizeDriverThreads() {
    if (const char* set = std::getenv("LP_NUM_THREADS")) return fmt::format("LP_NUM_THREADS={} (set by the user)", set);
    const std::string n = std::to_string(usableCpuCount());
    ::setenv("LP_NUM_THREADS", n.c_str(), 0);
    return fmt::format("LP_NUM_THREADS={} (from {})", n, cpuCount().source);
}

VKAPI_ATTR VkBool32 VKAPI_CALL Context::onValidationMessage(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT,
    const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    auto* self = static_cast<Context*>(user);
    // Known false positive of the Debian 12 SPIRV-Tools in the layers: `invariant gl_Position`
    // (spectral.vert) is a decoration on a gl_PerVertex member, which SPIR-V allows for built-ins.
    if (std::strstr(data->pMessage, "Decoration not allowed on struct members: SpvDecorationInvariant"))
        return VK_FALSE;
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        self->validationErrors_++;
        gValidationErrorsAtExit++;
        std::fprintf(stderr, "vulkan validation error: %s\n", data->pMessage);
    } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        std::fprintf(stderr, "vulkan validation warning: %s\n", data->pMessage);
    }
    return VK_FALSE;
}

uint32_t Context::validationErrorsAtExit() { return gValidationErrorsAtExit.load(); }

Context::Context(const ContextOptions& options) {
    validation_ = options.validation;
    if (validation_ && !hasLayer(kValidationLayer))
        failRuntime("validation requested but {} is not installed (apt-get install vulkan-validationlayers)",
                    kValidationLayer);

    const std::string driverThreads = sizeDriverThreads();
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "metamer";
    app.apiVersion = VK_API_VERSION_1_1;
    std::vector<const char*> extensions, layers;
    for (const auto& e : options.instanceExtensions) extensions.push_back(e.c_str());
    if (validation_) {
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
        layers.push_back(kValidationLayer);
    }
    VkDebugUtilsMessengerCreateInfoEXT messengerInfo{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    messengerInfo.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messengerInfo.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    messengerInfo.pfnUserCallback = &Context::onValidationMessage;
    messengerInfo.pUserData = this;

    VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ici.pApplicationInfo = &app;
    ici.enabledExtensionCount = uint32_t(extensions.size());
    ici.ppEnabledExtensionNames = extensions.data();
    ici.enabledLayerCount = uint32_t(layers.size());
    ici.ppEnabledLayerNames = layers.data();
    if (validation_) ici.pNext = &messengerInfo;  // also catches errors in vkCreate/DestroyInstance
    VkResult r = vkCreateInstance(&ici, nullptr, &instance_);
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED)
        failNoDevice(fmt::format("no Vulkan driver ({}); install mesa-vulkan-drivers for the CPU "
                                 "rasterizer lavapipe", resultName(r)));
    VK_CHECK(r);

    try {
        if (validation_) {
            auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
            VK_CHECK(create(instance_, &messengerInfo, nullptr, &messenger_));
            setObjectName_ = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
                vkGetInstanceProcAddr(instance_, "vkSetDebugUtilsObjectNameEXT"));
        }

        if (options.createSurface) {
            surface_ = options.createSurface(instance_);
            if (!surface_) failRuntime("Vulkan: the window's surface could not be created");
        }

        // Choose the device (vk/device_choice.h).
        auto devices = listDevices(instance_, surface_);
        DeviceRequest request;
        request.device = options.device;
        request.deviceFrom = options.deviceFrom;
        request.cudaVisibleDevices = options.cudaVisibleDevices;
        request.slurmLocalId = options.slurmLocalId;
        const DeviceChoice choice = chooseDevice(devices, request);
        const DeviceInfo* chosen = &devices[choice.position];
        deviceReason_ = choice.reason;
        info_ = *chosen;
        uint32_t n = 0;
        vkEnumeratePhysicalDevices(instance_, &n, nullptr);
        std::vector<VkPhysicalDevice> pds(n);
        vkEnumeratePhysicalDevices(instance_, &n, pds.data());
        physical_ = pds[info_.index];
        usable(physical_, &queueFamily_, surface_, &presentFamily_);
        vkGetPhysicalDeviceProperties(physical_, &properties_);
        vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
        if (options.verbose)
            std::fprintf(stderr, "metamer: device %u: %s, chosen by %s; %d thread%s (%s); %s\n", info_.index,
                         describeDevice(info_).c_str(), deviceReason_.c_str(), usableCpuCount(),
                         usableCpuCount() == 1 ? "" : "s", cpuCount().source.c_str(), driverThreads.c_str());

        float priority = 1.0f;
        VkDeviceQueueCreateInfo qci[2] = {{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO},
                                          {VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO}};
        qci[0].queueFamilyIndex = queueFamily_;
        qci[0].queueCount = 1;
        qci[0].pQueuePriorities = &priority;
        qci[1] = qci[0];
        qci[1].queueFamilyIndex = presentFamily_;
        const char* swapchain = VK_KHR_SWAPCHAIN_EXTENSION_NAME;
        VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
        dci.queueCreateInfoCount = presentFamily_ == queueFamily_ ? 1 : 2;
        dci.pQueueCreateInfos = qci;
        if (surface_) {
            dci.enabledExtensionCount = 1;
            dci.ppEnabledExtensionNames = &swapchain;
        }
        VK_CHECK(vkCreateDevice(physical_, &dci, nullptr, &device_));
        vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);
        vkGetDeviceQueue(device_, presentFamily_, 0, &presentQueue_);

        VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        pci.queueFamilyIndex = queueFamily_;
        VK_CHECK(vkCreateCommandPool(device_, &pci, nullptr, &commandPool_));
        pipelineCache_ = std::make_unique<PipelineCache>(device_, properties_, options.pipelineCacheFolder);
        objects_ = std::make_unique<DeviceObjects>(device_);
        if (options.verbose && !pipelineCache_->file().empty())
            std::fprintf(stderr, "metamer: pipeline cache %s (%zu bytes read%s)\n", pipelineCache_->file().c_str(),
                         pipelineCache_->loadedBytes(),
                         pipelineCache_->ignoredBecause().empty()
                             ? ""
                             : (", the file on disk ignored: " + pipelineCache_->ignoredBecause()).c_str());
    } catch (...) {
        release();
        throw;
    }
}

Context::~Context() { release(); }

VkPipelineCache Context::pipelineCache() const { return pipelineCache_ ? pipelineCache_->handle() : VK_NULL_HANDLE; }

void Context::release() {
    if (device_) {
        vkDeviceWaitIdle(device_);
        objects_.reset();        // every pass is gone: what the cache holds is destroyed here
        pipelineCache_.reset();  // written back to disk here
        if (commandPool_) vkDestroyCommandPool(device_, commandPool_, nullptr);
        vkDestroyDevice(device_, nullptr);  // the layers report leaked children here
    }
    if (surface_) vkDestroySurfaceKHR(instance_, surface_, nullptr);
    if (messenger_) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        destroy(instance_, messenger_, nullptr);
    }
    if (instance_) vkDestroyInstance(instance_, nullptr);
    device_ = VK_NULL_HANDLE;
    commandPool_ = VK_NULL_HANDLE;
    surface_ = VK_NULL_HANDLE;
    messenger_ = VK_NULL_HANDLE;
    instance_ = VK_NULL_HANDLE;
}

uint32_t Context::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required,
                                 VkMemoryPropertyFlags preferred) const {
    for (int pass = 0; pass < 2; ++pass) {
        VkMemoryPropertyFlags want = required | (pass == 0 ? preferred : 0);
        for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
            if ((typeBits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & want) == want) return i;
    }
    failRuntime("Vulkan: no memory type with flags {:#x} among bits {:#x}", required, typeBits);
}

VkCommandBuffer Context::beginOneTime() {
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = commandPool_;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cmd;
    VK_CHECK(vkAllocateCommandBuffers(device_, &ai, &cmd));
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(cmd, &bi));
    return cmd;
}

void Context::endOneTimeAndWait(VkCommandBuffer cmd) {
    VK_CHECK(vkEndCommandBuffer(cmd));
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence;
    VK_CHECK(vkCreateFence(device_, &fci, nullptr, &fence));
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    VkResult r = vkQueueSubmit(queue_, 1, &si, fence);
    if (r == VK_SUCCESS) r = vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX);
    vkDestroyFence(device_, fence, nullptr);
    vkFreeCommandBuffers(device_, commandPool_, 1, &cmd);
    VK_CHECK(r);
}

void Context::setName(VkObjectType type, uint64_t handle, const char* name) const {
    if (!setObjectName_) return;
    VkDebugUtilsObjectNameInfoEXT ni{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
    ni.objectType = type;
    ni.objectHandle = handle;
    ni.pObjectName = name;
    setObjectName_(device_, &ni);
}

}  // namespace metamer::vk
