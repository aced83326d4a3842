// OpenImageIO, loaded when something needs it: image formats other than EXR and PNG (JPEG, TIFF,
// … textures; `metamer compare` of such files) and the bench plot's text. Linking it would cost
// every process about 0.3 s at start (the dynamic loader resolving its ~260 libraries' symbols;
// docs/performance.md, "Start-up"), so it lives in a module of its own, libmetamer_oiio.so, built
// beside the metamer binary and opened with dlopen on first use (METAMER_OIIO_MODULE names
// another path). Tests: engine/io/raster_image_test.cpp, engine/bench/bench_test.cpp.
#pragma once

#include "io/raster_image.h"

#include <array>
#include <memory>
#include <string>

namespace metamer {

// A white RGB float canvas with OpenImageIO's drawing: lines, boxes and TrueType text.
class ImageCanvas {
public:
    using Color = std::array<float, 3>;
    enum class AlignX { Left, Right, Center };
    enum class AlignY { Baseline, Top, Bottom, Center };
    virtual ~ImageCanvas() = default;
    virtual void line(int x0, int y0, int x1, int y1, const Color& c) = 0;
    virtual void box(int x0, int y0, int x1, int y1, const Color& c, bool fill) = 0;
    // The box [x0, x1] × [y0, y1] the text covers with its baseline's left end at (0, 0); false
    // when the font cannot be used.
    virtual bool textBox(const std::string& text, int size, int& x0, int& y0, int& x1, int& y1) const = 0;
    virtual void text(const std::string& text, int x, int y, int size, const Color& c, AlignX ax, AlignY ay) = 0;
    // width × height × 3 floats, row 0 at the top.
    virtual std::vector<float> pixels() const = 0;
};

// What the module exports (one C entry point returns it); the version guards against a stale
// module left beside a newer binary.
struct OiioModuleApi {
    int version;
    // Each returns "" on success or what went wrong, for the caller to put in context. With
    // `headerOnly`, everything but the pixels (left empty): the caller checks the size first.
    std::string (*readFile)(const std::string& path, RasterImage& out, bool headerOnly);
    std::string (*readMemory)(const std::vector<uint8_t>& bytes, const std::string& format, RasterImage& out,
                              bool headerOnly);
    ImageCanvas* (*makeCanvas)(int width, int height, const std::string& font);
};
constexpr int kOiioModuleVersion = 2;
#define METAMER_OIIO_MODULE_ENTRY "metamer_oiio_module"

// The module, opened on first call; a runtime error names the path tried when it is missing.
const OiioModuleApi& oiioModule();
// Whether this process has opened it (for tests and the start-up figures).
bool oiioModuleLoaded();

// An image in any format OpenImageIO reads; input errors name `where`. The header is read first
// and handed to `check` (raster_image.h) before the pixels are decoded.
RasterImage readWithOpenImageIO(const std::filesystem::path& path, const Where& where, const ImageHeaderCheck& check);
RasterImage readWithOpenImageIO(const std::vector<uint8_t>& bytes, const std::string& format, const Where& where,
                                const ImageHeaderCheck& check);
std::unique_ptr<ImageCanvas> makeImageCanvas(int width, int height, const std::filesystem::path& font);

}  // namespace metamer
