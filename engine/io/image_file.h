// Writing an ordinary (non-spectral) image — display PNGs, XYZ and detector-response EXRs —
// through OpenImageIO and AtomicOutput: the file appears whole or not at all.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

struct ImageFile {
    int width = 0, height = 0;
    std::vector<std::string> channels;                    // names, e.g. {"R","G","B"} or {"X","Y","Z"}
    std::vector<std::pair<std::string, std::string>> attributes;  // string metadata
};

// 8- or 16-bit integer pixels (PNG), `channels.size()` per pixel, row 0 at the top.
void writeImage(const std::filesystem::path& path, const ImageFile& image, const std::vector<uint16_t>& pixels,
                int bits);
// float32 pixels (EXR, zip compression).
void writeImage(const std::filesystem::path& path, const ImageFile& image, const std::vector<float>& pixels);

}  // namespace metamer
