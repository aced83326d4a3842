// The chunk types of a PNG file, in order ("IHDR", "sRGB", "iCCP", …), read from its bytes: what
// tests check a colour tag with, since OpenImageIO reports an untagged PNG as sRGB too.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace metamer::test {

inline std::vector<std::string> pngChunkTypes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::string> types;
    // An 8-byte signature, then chunks: a 4-byte big-endian length, the type, the data, a CRC.
    for (size_t at = 8; at + 8 <= bytes.size();) {
        uint32_t length = 0;
        for (int k = 0; k < 4; ++k) length = (length << 8) | uint8_t(bytes[at + size_t(k)]);
        types.push_back(bytes.substr(at + 4, 4));
        at += 12 + size_t(length);
    }
    return types;
}

inline bool hasPngChunk(const std::filesystem::path& path, const std::string& type) {
    for (const std::string& t : pngChunkTypes(path))
        if (t == type) return true;
    return false;
}

}  // namespace metamer::test
