// Writing an ordinary (non-spectral) image — display PNGs (libpng, io/png_file), XYZ and
// detector-response EXRs (OpenEXR, io/exr_file) — through AtomicOutput: the file appears whole or
// not at all. The format comes from the extension: .png or .exr.
// Tests: engine/compare/compare_test.cpp, tests/cli_test.cpp.
#pragma once

#include "io/exr_file.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

class AtomicOutput;

struct ImageFile {
    int width = 0, height = 0;
    std::vector<std::string> channels;                    // names, e.g. {"R","G","B"} or {"X","Y","Z"}
    std::vector<std::pair<std::string, std::string>> attributes;  // string metadata
    std::vector<uint8_t> iccProfile;  // PNG: the colour space's ICC profile (io/png_file.h), if any
    // EXR: what R, G, B mean (io/exr_file.h), if not BT.709 with D65 — XYZ in R, G, B, for one
    std::optional<ExrChromaticities> chromaticities;
};

// Writes an image strip by strip (rows in order); the file appears only at commit().
class ImageFileWriter {
public:
    // bits: 8 or 16 for PNG, 32 for EXR (float, piz).
    ImageFileWriter(const std::filesystem::path& path, const ImageFile& image, int bits);
    ~ImageFileWriter();
    ImageFileWriter(const ImageFileWriter&) = delete;
    ImageFileWriter& operator=(const ImageFileWriter&) = delete;
    void writeRows(int firstRow, int rows, const std::vector<uint16_t>& pixels);  // 8/16 bits
    void writeRows(int firstRow, int rows, const std::vector<float>& pixels);     // 32 bits
    // Completes the temporary file and returns it for commitTogether (io/atomic_file.h),
    // which renames a run's files into place together; commit() is finish() and that.
    std::vector<AtomicOutput*> finish();
    void commit();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// 8- or 16-bit integer pixels (PNG), `channels.size()` per pixel, row 0 at the top.
void writeImage(const std::filesystem::path& path, const ImageFile& image, const std::vector<uint16_t>& pixels,
                int bits);
// float32 pixels (EXR, zip compression).
void writeImage(const std::filesystem::path& path, const ImageFile& image, const std::vector<float>& pixels);

}  // namespace metamer
