// The display counts as the window's bytes, and back. The swapchain holds 8 bits per channel:
// 8-bit counts are copied unchanged; 16-bit counts are shown rounded to 8 bits, c·255/65535.
#pragma once

#include "color/tonemap.h"

#include <cstdint>
#include <vector>

namespace metamer::preview {

// An 8-bit count for a count of a `bits`-bit display (8 or 16).
uint8_t windowCount(uint16_t count, int bits);

// image.counts (3 per pixel) as 4 bytes per pixel, B G R A (bgra) or R G B A, alpha 255.
std::vector<uint8_t> toWindowBytes(const DisplayImage& image, int bits, bool bgra);

// The rectangle (x, y, width, height) of a frame read back from the swapchain (frameWidth × … ×
// 4 bytes in its byte order) as R G B counts, 3 per pixel, row 0 at the top: what the window
// showed there. The rectangle must lie inside the frame.
std::vector<uint16_t> fromWindowBytes(const std::vector<uint8_t>& frame, int frameWidth, int frameHeight, bool bgra,
                                      int x, int y, int width, int height);

}  // namespace metamer::preview
