#include "preview/display_bytes.h"

#include "core/error.h"

#include <algorithm>

namespace metamer::preview {

uint8_t windowCount(uint16_t count, int bits) {
    if (bits == 8) return uint8_t(std::min<uint16_t>(count, 255));
    return uint8_t((uint32_t(count) * 255u + 32767u) / 65535u);  // rounded to the nearest 8-bit count
}

std::vector<uint8_t> toWindowBytes(const DisplayImage& image, int bits, bool bgra) {
    const size_t n = size_t(image.width) * image.height;
    if (image.counts.size() != 3 * n) failRuntime("preview: the display image has no counts to show");
    std::vector<uint8_t> out(4 * n);
    const int r = bgra ? 2 : 0, b = bgra ? 0 : 2;
    for (size_t i = 0; i < n; ++i) {
        out[4 * i + r] = windowCount(image.counts[3 * i], bits);
        out[4 * i + 1] = windowCount(image.counts[3 * i + 1], bits);
        out[4 * i + b] = windowCount(image.counts[3 * i + 2], bits);
        out[4 * i + 3] = 255;
    }
    return out;
}

std::vector<uint16_t> fromWindowBytes(const std::vector<uint8_t>& frame, int frameWidth, int frameHeight, bool bgra,
                                      int x, int y, int width, int height) {
    if (x < 0 || y < 0 || width < 0 || height < 0 || x + width > frameWidth || y + height > frameHeight ||
        frame.size() != size_t(frameWidth) * frameHeight * 4)
        failRuntime("preview: the {}×{} region at {},{} is not inside the {}×{} frame", width, height, x, y, frameWidth,
                    frameHeight);
    std::vector<uint16_t> out(size_t(width) * height * 3);
    const int r = bgra ? 2 : 0, b = bgra ? 0 : 2;
    for (int row = 0; row < height; ++row)
        for (int col = 0; col < width; ++col) {
            const uint8_t* p = &frame[(size_t(y + row) * frameWidth + (x + col)) * 4];
            uint16_t* o = &out[(size_t(row) * width + col) * 3];
            o[0] = p[r];
            o[1] = p[1];
            o[2] = p[b];
        }
    return out;
}

}  // namespace metamer::preview
