#include "vk/device_choice.h"

#include "core/error.h"

#include <gtest/gtest.h>

using namespace metamer;
using namespace metamer::vk;

namespace {

// A node with lavapipe first and two GPUs, as the Vulkan loader may list them.
std::vector<DeviceInfo> node() {
    return {{0, "llvmpipe (LLVM 15.0.6, 256 bits)", VK_PHYSICAL_DEVICE_TYPE_CPU, 100, "6d657361-3135-2e30-2e36-000000000000"},
            {1, "NVIDIA H100", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, 400, "8932f937-d72c-4106-c12f-20bd9faed9f6"},
            {2, "NVIDIA H100", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, 400, "1a2b3c4d-0000-1111-2222-333344445555"}};
}

std::string noDeviceError(const std::vector<DeviceInfo>& devices, const DeviceRequest& r) {
    try {
        chooseDevice(devices, r);
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::NoDevice) << e.text();
        return e.text();
    }
    return "";
}

}  // namespace

TEST(DeviceChoice, MetamerDeviceWinsAndTakesAnIndexAUuidOrAName) {
    DeviceRequest r;
    r.device = "0";
    r.cudaVisibleDevices = "1";
    r.slurmLocalId = "1";
    EXPECT_EQ(chooseDevice(node(), r).position, 0u);
    EXPECT_EQ(chooseDevice(node(), r).reason, "METAMER_DEVICE=0");
    r.device = "GPU-1a2b3c4d-0000-1111-2222-333344445555";
    EXPECT_EQ(chooseDevice(node(), r).position, 2u);
    r.device = "8932F937D72C4106C12F20BD9FAED9F6";  // without dashes, upper case
    EXPECT_EQ(chooseDevice(node(), r).position, 1u);
    r.device = "llvm";
    EXPECT_EQ(chooseDevice(node(), r).position, 0u);
}

TEST(DeviceChoice, CudaVisibleDevicesCountsGpusAndMatchesUuids) {
    DeviceRequest r;
    r.cudaVisibleDevices = "1,0";  // the first entry is this process's GPU: the second GPU
    r.slurmLocalId = "0";
    EXPECT_EQ(chooseDevice(node(), r).position, 2u);
    r.cudaVisibleDevices = "GPU-8932f937";  // a unique prefix, as CUDA accepts
    EXPECT_EQ(chooseDevice(node(), r).position, 1u);
    r.cudaVisibleDevices = "NoDevFiles";  // Slurm without GPUs: skipped, SLURM_LOCALID decides
    EXPECT_EQ(chooseDevice(node(), r).position, 1u);
    // lavapipe alone: the index counts every device.
    r.cudaVisibleDevices = "0";
    EXPECT_EQ(chooseDevice({node()[0]}, r).position, 0u);
}

TEST(DeviceChoice, SlurmLocalIdSpreadsTasksOverTheGpus) {
    DeviceRequest r;
    for (int id = 0; id < 4; ++id) {
        r.slurmLocalId = std::to_string(id);
        EXPECT_EQ(chooseDevice(node(), r).position, size_t(1 + id % 2));
    }
    EXPECT_EQ(chooseDevice(node(), r).reason, "SLURM_LOCALID=3 (of 2 GPUs)");
    EXPECT_EQ(chooseDevice({node()[0]}, r).position, 0u);  // lavapipe only: 3 mod 1
}

TEST(DeviceChoice, WithoutARequestTheBestScore) {
    EXPECT_EQ(chooseDevice(node(), {}).position, 1u);
    EXPECT_EQ(chooseDevice(node(), {}).reason, "the best score");
}

TEST(DeviceChoice, WhatMatchesNothingIsAClearError) {
    DeviceRequest r;
    r.device = "5";
    EXPECT_NE(noDeviceError(node(), r).find("METAMER_DEVICE='5' is not a device index; the devices: 0: llvmpipe"),
              std::string::npos);
    r.device = "GPU-ffffffff-0000-0000-0000-000000000000";
    const std::string uuid = noDeviceError(node(), r);
    EXPECT_NE(uuid.find("is not the UUID of any Vulkan device"), std::string::npos) << uuid;
    EXPECT_NE(uuid.find("UUID 8932f937-d72c-4106-c12f-20bd9faed9f6"), std::string::npos) << uuid;
    r = {};
    r.cudaVisibleDevices = "GPU-deadbeef";
    EXPECT_NE(noDeviceError(node(), r).find("CUDA_VISIBLE_DEVICES='GPU-deadbeef' is not the UUID"), std::string::npos);
    r.cudaVisibleDevices = "2";
    EXPECT_NE(noDeviceError(node(), r).find("names GPU 2, but Vulkan sees 2 GPU(s)"), std::string::npos);
    r.cudaVisibleDevices = "MIG-12345";
    EXPECT_NE(noDeviceError(node(), r).find("MIG instance"), std::string::npos);
    r = {};
    r.slurmLocalId = "x";
    try {
        chooseDevice(node(), r);
        FAIL() << "accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(e.text().find("SLURM_LOCALID: 'x'"), std::string::npos) << e.text();
    }
}

TEST(DeviceChoice, AnUnusableChoiceIsRefused) {
    std::vector<DeviceInfo> devices = node();
    devices[2].score = 0;
    DeviceRequest r;
    r.device = "2";
    EXPECT_NE(noDeviceError(devices, r).find("lacks a graphics queue"), std::string::npos);
}
