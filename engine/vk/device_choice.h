// Which Vulkan device a process renders with, from what the user and the scheduler said, first
// match wins: --device or METAMER_DEVICE (an index, a UUID, or a name substring), else
// CUDA_VISIBLE_DEVICES (its first entry: an index among the GPUs, or a UUID, "GPU-" prefix and
// unique prefixes accepted, as CUDA does), else SLURM_LOCALID (task i of a node takes GPU i mod the
// GPU count), else the best score (discrete > integrated > virtual > CPU). "The GPUs" are the
// devices that are not CPU rasterizers, or, on a machine without one, every device (so that a
// lavapipe-only node still honours the variables). A pure function of the device list, so the
// rules are tested without the hardware. docs/cli.md, "Devices".
// Tests: engine/vk/device_choice_test.cpp, tests/cli_test.cpp (CliDevices.*).
#pragma once

#include "vk/check.h"

#include <cstdint>
#include <string>
#include <vector>

namespace metamer::vk {

struct DeviceInfo {
    uint32_t index = 0;
    std::string name;
    VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
    int score = 0;     // 0: unusable (no graphics queue, no RGBA32F/D32 targets, or cannot present)
    std::string uuid;  // VkPhysicalDeviceIDProperties::deviceUUID as 8-4-4-4-12 hex; empty before Vulkan 1.1
};

// What the user and the scheduler asked for; empty strings are unset.
struct DeviceRequest {
    std::string device;                      // --device or METAMER_DEVICE
    std::string deviceFrom = "METAMER_DEVICE";  // which of the two, for messages
    std::string cudaVisibleDevices;          // CUDA_VISIBLE_DEVICES
    std::string slurmLocalId;                // SLURM_LOCALID
};

// The request from the environment (METAMER_DEVICE, CUDA_VISIBLE_DEVICES, SLURM_LOCALID).
DeviceRequest deviceRequestFromEnvironment();

struct DeviceChoice {
    size_t position = 0;  // into the list given
    std::string reason;   // "METAMER_DEVICE=0", "SLURM_LOCALID=3 (of 2 GPUs)", "the best score"
};

// The device to use among `devices` (non-empty). A request that matches none, or a usable device
// that is not, is Error(ExitCode::NoDevice) naming the variable, its value and the devices; a value
// that cannot be read (SLURM_LOCALID=x) is an input error naming the variable.
DeviceChoice chooseDevice(const std::vector<DeviceInfo>& devices, const DeviceRequest& request);

// "llvmpipe (CPU)": a device and its type, for messages.
std::string describeDevice(const DeviceInfo& device);
const char* deviceTypeName(VkPhysicalDeviceType type);

}  // namespace metamer::vk
