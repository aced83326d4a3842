#include "vk/device_choice.h"

#include "core/error.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace metamer::vk {

namespace {

[[noreturn]] void failNoDevice(const std::string& why) {
    throw Error(ExitCode::NoDevice, Where{}, "no usable Vulkan device: " + why);
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

std::string trimmed(const std::string& s) {
    const size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
    return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// The UUID's hex digits, lower case, without "GPU-" and dashes ("" when it is not a UUID's text).
std::string uuidDigits(const std::string& text) {
    std::string t = lower(text);
    if (t.rfind("gpu-", 0) == 0) t = t.substr(4);
    std::string digits;
    for (char c : t) {
        if (c == '-') continue;
        if (!std::isxdigit(static_cast<unsigned char>(c))) return "";
        digits += c;
    }
    return digits;
}

// A UUID is written "GPU-…" (nvidia-smi -L, CUDA_VISIBLE_DEVICES) or as its 32 hex digits.
bool looksLikeUuid(const std::string& text) {
    return lower(text).rfind("gpu-", 0) == 0 || uuidDigits(text).size() == 32;
}

bool isWholeNumber(const std::string& text) {
    return !text.empty() && std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); });
}

std::string listed(const std::vector<DeviceInfo>& devices) {
    std::string all;
    for (const auto& d : devices)
        all += fmt::format("{}{}: {}{}", all.empty() ? "" : ", ", d.index, describeDevice(d),
                           d.uuid.empty() ? "" : " UUID " + d.uuid);
    return all;
}

// The devices "an index among the GPUs" counts: those that are not CPU rasterizers, else all.
std::vector<size_t> gpus(const std::vector<DeviceInfo>& devices) {
    std::vector<size_t> out;
    for (size_t i = 0; i < devices.size(); ++i)
        if (devices[i].type != VK_PHYSICAL_DEVICE_TYPE_CPU) out.push_back(i);
    if (out.empty())
        for (size_t i = 0; i < devices.size(); ++i) out.push_back(i);
    return out;
}

// The one device whose UUID starts with the digits of `text` (the whole UUID, or a unique prefix
// written "GPU-…"); `what` names the setting in the error.
size_t byUuid(const std::vector<DeviceInfo>& devices, const std::string& text, const std::string& what) {
    const std::string want = uuidDigits(text);
    std::vector<size_t> hits;
    for (size_t i = 0; i < devices.size(); ++i)
        if (!want.empty() && !devices[i].uuid.empty() && uuidDigits(devices[i].uuid).rfind(want, 0) == 0) hits.push_back(i);
    if (hits.size() == 1) return hits[0];
    failNoDevice(fmt::format("{}='{}' {} the UUID of {} Vulkan device; the devices: {} (metamer devices lists them)",
                             what, text, hits.empty() ? "is not" : "is the start of", hits.empty() ? "any" : "more than one",
                             listed(devices)));
}

}  // namespace

const char* deviceTypeName(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
        default: return "other";
    }
}

std::string describeDevice(const DeviceInfo& d) { return fmt::format("{} ({})", d.name, deviceTypeName(d.type)); }

DeviceRequest deviceRequestFromEnvironment() {
    DeviceRequest r;
    if (const char* v = std::getenv("METAMER_DEVICE")) r.device = v;
    if (const char* v = std::getenv("CUDA_VISIBLE_DEVICES")) r.cudaVisibleDevices = v;
    if (const char* v = std::getenv("SLURM_LOCALID")) r.slurmLocalId = v;
    return r;
}

DeviceChoice chooseDevice(const std::vector<DeviceInfo>& devices, const DeviceRequest& request) {
    if (devices.empty()) failNoDevice("the Vulkan loader found no device (is mesa-vulkan-drivers installed?)");
    auto usableOrFail = [&](size_t at, std::string reason) {
        if (devices[at].score == 0)
            failNoDevice(fmt::format("{} chose device {}: {}, which lacks a graphics queue or RGBA32F/D32 render "
                                     "targets (or cannot present to the window)",
                                     reason, devices[at].index, describeDevice(devices[at])));
        return DeviceChoice{at, std::move(reason)};
    };

    // 1. --device or METAMER_DEVICE: an index into the whole list, a UUID, or a name substring.
    if (!request.device.empty()) {
        const std::string& want = request.device;
        const std::string reason = fmt::format("{}={}", request.deviceFrom, want);
        if (isWholeNumber(want)) {
            for (size_t i = 0; i < devices.size(); ++i)
                if (devices[i].index == std::strtoul(want.c_str(), nullptr, 10))
                    return usableOrFail(i, reason);
            failNoDevice(fmt::format("{}='{}' is not a device index; the devices: {}", request.deviceFrom, want,
                                     listed(devices)));
        }
        if (looksLikeUuid(want)) return usableOrFail(byUuid(devices, want, request.deviceFrom), reason);
        for (size_t i = 0; i < devices.size(); ++i)
            if (lower(devices[i].name).find(lower(want)) != std::string::npos) return usableOrFail(i, reason);
        failNoDevice(fmt::format("{}='{}' matches none of: {}", request.deviceFrom, want, listed(devices)));
    }

    // 2. CUDA_VISIBLE_DEVICES, as a scheduler's GPU binding sets it: the first entry is this
    //    process's GPU. "", "NoDevFiles" (Slurm without GPUs) and negative entries mean none: skipped.
    const std::string cuda = trimmed(request.cudaVisibleDevices.substr(0, request.cudaVisibleDevices.find(',')));
    if (!cuda.empty() && cuda != "NoDevFiles" && cuda[0] != '-') {
        const std::string reason = fmt::format("CUDA_VISIBLE_DEVICES={}", request.cudaVisibleDevices);
        if (lower(cuda).rfind("mig-", 0) == 0)
            failNoDevice(fmt::format("CUDA_VISIBLE_DEVICES='{}' names a MIG instance, which Vulkan cannot use; "
                                     "name a whole GPU's UUID (nvidia-smi -L) in METAMER_DEVICE", cuda));
        if (isWholeNumber(cuda)) {
            const std::vector<size_t> candidates = gpus(devices);
            const unsigned long n = std::strtoul(cuda.c_str(), nullptr, 10);
            if (n >= candidates.size())
                failNoDevice(fmt::format("CUDA_VISIBLE_DEVICES='{}' names GPU {}, but Vulkan sees {} GPU(s): {}; "
                                         "a UUID (nvidia-smi -L) does not depend on the order",
                                         request.cudaVisibleDevices, n, candidates.size(), listed(devices)));
            return usableOrFail(candidates[n], reason);
        }
        return usableOrFail(byUuid(devices, cuda, "CUDA_VISIBLE_DEVICES"), reason);
    }

    // 3. SLURM_LOCALID: the task's rank on its node, spread over the usable GPUs.
    if (!request.slurmLocalId.empty()) {
        if (!isWholeNumber(request.slurmLocalId))
            failInput(Where{"", "SLURM_LOCALID"}, "'{}' is not a task's local id; expected a whole number from 0",
                      request.slurmLocalId);
        std::vector<size_t> candidates;
        for (size_t i : gpus(devices))
            if (devices[i].score > 0) candidates.push_back(i);
        if (!candidates.empty()) {
            const unsigned long id = std::strtoul(request.slurmLocalId.c_str(), nullptr, 10);
            return {candidates[id % candidates.size()],
                    fmt::format("SLURM_LOCALID={} (of {} GPU{})", request.slurmLocalId, candidates.size(),
                                candidates.size() == 1 ? "" : "s")};
        }
    }

    // 4. The best score.
    const DeviceInfo* best = nullptr;
    size_t at = 0;
    for (size_t i = 0; i < devices.size(); ++i)
        if (devices[i].score > 0 && (!best || devices[i].score > best->score)) {
            best = &devices[i];
            at = i;
        }
    if (!best)
        failNoDevice(fmt::format("none has a graphics queue and RGBA32F/D32 render targets (or presents to the "
                                 "window): {}", listed(devices)));
    return {at, "the best score"};
}

}  // namespace metamer::vk
