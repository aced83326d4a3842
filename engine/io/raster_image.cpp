#include "io/raster_image.h"

#include <cmath>

namespace metamer {

std::string RasterImage::attribute(const std::string& name) const {
    for (const auto& [k, v] : attributes)
        if (k == name) return v;
    return "";
}

float RasterImage::normalized(size_t i) const {
    return floatingPoint ? pixels[i] : float(double(pixels[i]) / (std::ldexp(1.0, bits) - 1.0));
}

}  // namespace metamer
