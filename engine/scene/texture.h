// Texture files of a material (docs/scene-format.md, "Textures"): reflective spectral EXRs, RGB
// images and normal or bump maps, read into a Texture (scene/scene.h). Resampling onto the render
// grid and RGB up-sampling happen later, in scene/scene_on_grid.
// Tests: tests/textures_test.cpp, tests/bad-inputs (the texture- and cube- cases).
#pragma once

#include "core/error.h"
#include "scene/scene.h"

#include <filesystem>
#include <string>
#include <vector>

namespace metamer {

enum class TextureRole {
    Reflectance,  // diffuse or specular: a spectral EXR (T.<λ>nm channels) or an RGB image
    Normal,       // a tangent-space normal map: RGB = (n + 1)/2, +y up the image (glTF's convention)
    Height,       // a bump map: one channel of height in [0, 1], turned into a normal map
    Scalar,       // a map of numbers ≥ 0: one channel, read linearly (a paint layer's thickness factor)
};

enum class TextureEncoding {
    Auto,    // sRGB for 8- and 16-bit integer files (PNG, JPEG, TIFF), linear for float files (EXR)
    Srgb,    // the sRGB transfer function (IEC 61966-2-1) is removed on load
    Linear,  // values are linear reflectance as stored
};

// Largest texture side, texels (larger files are refused with their size).
constexpr int kMaxTextureSide = 16384;

// The most a scene's textures may take on the grid (W·H·bands float32 texels each, normal maps
// 3): 8 GiB, or a quarter of the machine's memory when that is less (core/memory_limits.h).
uint64_t textureMemoryLimit();

// Reads `path` for `role`. `bumpScale` (Height only) is the height difference, in texel widths,
// that a value step of 1 in the file stands for: the bump's slope is bumpScale × the value's
// central difference per texel. Input errors name `where` (the scene key) and the file. A texture
// over kMaxTextureSide, or (given the `grid` it will be resampled to) one that alone would take
// more than textureMemoryLimit() there, is refused from the file's header, before decoding.
Texture loadTexture(const std::filesystem::path& path, TextureRole role, TextureEncoding encoding,
                    double bumpScale, const Where& where, const Grid* grid = nullptr);

// An image held in memory — a glTF file's embedded PNG or JPEG — and the name messages give it.
struct EncodedImage {
    std::string name;
    const std::vector<unsigned char>& bytes;
};

// As loadTexture, for an embedded PNG or JPEG (any other bytes are an input error naming it).
Texture loadTexture(const EncodedImage& image, TextureRole role, TextureEncoding encoding, double bumpScale,
                    const Where& where, const Grid* grid = nullptr);

// A height field (width × height values, row 0 at the top, repeating at the edges) turned into
// tangent-space unit normals: n ∝ (−s·∂h/∂x, s·∂h/∂y_up, 1) with central differences per texel.
std::vector<float> heightToNormals(const std::vector<float>& height, int width, int height_px, double scale);

}  // namespace metamer
