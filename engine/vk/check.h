// VK_CHECK: always on. A failing Vulkan call is a runtime error that names the call and result.
// Tests: through the GPU tests (tests/support/gpu.h).
#pragma once

#include "core/error.h"

#include <vulkan/vulkan.h>

namespace metamer::vk {

const char* resultName(VkResult r);

}  // namespace metamer::vk

#define VK_CHECK(call)                                                                       \
    do {                                                                                     \
        VkResult vkCheckResult_ = (call);                                                    \
        if (vkCheckResult_ != VK_SUCCESS)                                                    \
            ::metamer::failRuntime("Vulkan: {} failed: {} ({}:{})", #call,                   \
                                   ::metamer::vk::resultName(vkCheckResult_), __FILE__, __LINE__); \
    } while (0)
