#include "core/memory_limits.h"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <unistd.h>

namespace metamer {

namespace {

// The number in a cgroup file, or 0 ("max", missing, unreadable).
uint64_t cgroupLimit(const char* path) {
    std::ifstream f(path);
    std::string text;
    if (!(f >> text) || text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return 0;
    try {
        return std::stoull(text);
    } catch (...) {
        return 0;
    }
}

}  // namespace

uint64_t machineMemoryBytes() {
    static const uint64_t bytes = [] {
        const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
        uint64_t m = pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) : uint64_t(8) << 30;
        for (const char* p : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"})
            if (const uint64_t limit = cgroupLimit(p); limit > 0) m = std::min(m, limit);
        return m;
    }();
    return bytes;
}

uint64_t decodedImageLimitBytes() { return machineMemoryBytes() / 4; }

void requireDecodableSize(uint64_t width, uint64_t height, uint64_t channels, uint64_t bytesPerValue,
                          uint64_t decoderBytes, const Where& where, const std::string& what) {
    // In long double: a hostile header's 2^31 × 2^31 × 2^31 must not wrap around to a small size.
    const long double bytes =
        (long double)width * (long double)height * (long double)channels * (long double)bytesPerValue +
        (long double)decoderBytes;
    const uint64_t limit = decodedImageLimitBytes();
    if (bytes <= (long double)limit) return;
    failInput(where, "{} is {}×{} with {} channel{}: decoded it would take {}; the limit is {}, a quarter of this "
              "machine's memory ({})", what, width, height, channels, channels == 1 ? "" : "s",
              bytes >= 1e18L ? fmt::format("{:.3g} bytes", double(bytes)) : memorySize(uint64_t(bytes)),
              memorySize(limit), memorySize(machineMemoryBytes()));
}

std::string memorySize(uint64_t bytes) {
    if (bytes >= (uint64_t(1) << 30)) return fmt::format("{:.1f} GiB", double(bytes) / double(uint64_t(1) << 30));
    return fmt::format("{:.1f} MiB", double(bytes) / double(1 << 20));
}

}  // namespace metamer
