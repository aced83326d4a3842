#include "scene/texture.h"

#include "color/srgb.h"
#include "core/file_reads.h"
#include "core/memory_limits.h"
#include "io/exr_file.h"
#include "io/image_reader.h"
#include "io/spectral_exr.h"
#include "io/spectral_image.h"
#include "spectral/spectrum.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace metamer {

namespace fs = std::filesystem;

namespace {

// Every texel finite; reflectance outside [0, 1] is suspicious but can be measurement noise, so
// it is a warning with a count and the first offender (as for sampled spectra).
void checkReflectance(const Texture& t, const Where& where) {
    size_t outside = 0, first = 0;
    for (size_t i = 0; i < t.texels.size(); ++i) {
        float v = t.texels[i];
        if (!std::isfinite(v)) {
            size_t texel = i / t.channels;
            failInput(where, "texture '{}': texel ({}, {}) channel {} is {}; expected a finite reflectance",
                      t.file.string(), texel % t.width, texel / t.width, i % t.channels, v);
        }
        if (std::fabs(v) > kMaxRatio) {  // float32 past the GPU's products (spectral/spectrum.h)
            size_t texel = i / t.channels;
            failInput(where, "texture '{}': texel ({}, {}) channel {} is {:g}; a reflectance outside [0, 1] is warned "
                             "about and rendered within ±{:g}, no further",
                      t.file.string(), texel % t.width, texel / t.width, i % t.channels, v, kMaxRatio);
        }
        if ((v < 0.0f || v > 1.0f) && outside++ == 0) first = i;
    }
    if (outside > 0) {
        size_t texel = first / t.channels;
        warn(where, fmt::format("texture '{}': {} value(s) outside [0, 1] (first: texel ({}, {}) channel {} = {:g}); "
                                "used as given",
                                t.file.string(), outside, texel % t.width, texel / t.width, first % t.channels,
                                t.texels[first]));
    }
}

void checkSize(int width, int height, const std::string& name, const Where& where) {
    if (width < 1 || height < 1 || width > kMaxTextureSide || height > kMaxTextureSide)
        failInput(where, "texture '{}' is {}×{} texels; expected 1 to {} per side", name, width, height,
                  kMaxTextureSide);
}

// Whether `e` was raised at the scene key `where` (not inside the image reader, whose errors name
// the file alone and are put in the texture's context).
bool isAt(const Error& e, const Where& where) { return e.where().file == where.file && e.where().key == where.key; }

// A reader's message without its own "not a readable image: ", which the texture's context says.
std::string withoutPrefix(const std::string& message) {
    const std::string prefix = "not a readable image: ";
    return message.rfind(prefix, 0) == 0 ? message.substr(prefix.size()) : message;
}

const char* roleName(TextureRole role) {
    switch (role) {
        case TextureRole::Reflectance: return "reflectance";
        case TextureRole::Normal: return "normal";
        case TextureRole::Height: return "bump";
        case TextureRole::Scalar: return "thickness";
    }
    return "?";
}

// What a texture's header must pass before its texels are decoded: its side, and (given the grid
// it goes to) its size there.
ImageHeaderCheck textureHeaderCheck(const std::string& name, TextureRole role, const Grid* grid, const Where& where) {
    return [name, role, grid, where](const RasterImage& h) {
        checkSize(h.width, h.height, name, where);
        if (!grid) return;
        // A scalar map becomes a spectrum per texel on the grid (a paint layer's reflectance).
        const uint64_t perTexel =
            role == TextureRole::Reflectance || role == TextureRole::Scalar ? uint64_t(grid->bands()) : 3;
        const uint64_t bytes = uint64_t(h.width) * uint64_t(h.height) * perTexel * 4;
        if (bytes > textureMemoryLimit())
            failInput(where, "texture '{}' is {}×{} texels: on the grid {} nm ({} values × 4 bytes per texel) it would "
                      "take {}; the limit is {} (8 GiB, or a quarter of this machine's memory when less): use a "
                      "smaller texture or a coarser grid", name, h.width, h.height, grid->str(), perTexel,
                      memorySize(bytes), memorySize(textureMemoryLimit()));
    };
}

Texture readSpectral(const fs::path& path, const Where& where, const ImageHeaderCheck& check) {
    SpectralExrImage image;
    try {
        image = readSpectralImage(path, [&](int width, int height, int) {
            RasterImage header;
            header.width = width;
            header.height = height;
            check(header);
        });
    } catch (const Error& e) {
        if (isAt(e, where)) throw;  // the texture check's own error: as it is
        failInput(where, "{}", e.text());
    }
    if (image.component != SpectralComponent::Reflective)
        failInput(where,
                  "texture '{}' holds spectral radiance (EXR S0.<λ>nm channels, or an HDF5/ENVI cube whose "
                  "quantity is not reflectance); a reflectance texture has T.<λ>nm channels or quantity reflectance",
                  path.string());
    Texture t;
    t.kind = Texture::Kind::Spectral;
    t.file = path;
    t.width = image.cube.width;
    t.height = image.cube.height;
    checkSize(t.width, t.height, path.string(), where);
    t.wavelengths_nm = image.cube.grid.wavelengths();
    t.channels = int(t.wavelengths_nm.size());
    if (t.channels < 2)
        failInput(where, "texture '{}' has one spectral channel ({:g} nm); a reflectance spectrum needs at least two",
                  path.string(), t.wavelengths_nm[0]);
    t.texels = std::move(image.cube.data);
    checkReflectance(t, where);
    return t;
}

// An image as float RGB (grey is replicated, alpha and other channels are dropped; integer
// counts scaled to 0 … 1), with its encoding decided. `name` is the file or the embedded image,
// for messages.
std::vector<float> readRgb(const RasterImage& in, const std::string& name, TextureEncoding encoding,
                           const Where& where, int& width, int& height, bool& wasFloat) {
    checkSize(in.width, in.height, name, where);
    const int n = int(in.channels.size());
    if (n != 1 && n != 3 && n != 4)
        failInput(where, "texture '{}' has {} channels; expected 1 (grey), 3 (RGB) or 4 (RGBA)", name, n);
    width = in.width;
    height = in.height;
    wasFloat = in.floatingPoint;
    bool srgb = encoding == TextureEncoding::Srgb || (encoding == TextureEncoding::Auto && !wasFloat);
    std::vector<float> rgb(size_t(width) * height * 3);
    for (size_t p = 0; p < size_t(width) * height; ++p)
        for (int c = 0; c < 3; ++c) {
            float v = in.normalized(p * n + (n == 1 ? 0 : c));
            rgb[p * 3 + c] = srgb ? float(srgbDecode(double(v))) : v;
        }
    return rgb;
}

// Reads an image for a texture; its errors name the texture and the scene's key.
RasterImage readTextureImage(const fs::path& path, const Where& where, const ImageHeaderCheck& check) {
    try {
        return readRasterImage(path, Where{path.string()}, check);
    } catch (const Error& e) {
        if (e.code() != ExitCode::BadInput || isAt(e, where)) throw;  // the header check's own error: as it is
        failInput(where, "texture '{}' is not a readable image: {}", path.string(), withoutPrefix(e.message()));
    }
}

// An RGB, normal or height texture from an image: what loadTexture does after the file's kind is
// known.
Texture imageTexture(const RasterImage& in, const std::string& name, TextureRole role, TextureEncoding encoding,
                     double bumpScale, const Where& where) {
    Texture t;
    t.file = name;
    bool wasFloat = false;
    // Normal and height maps are data, never sRGB-encoded, whatever the file type.
    TextureEncoding e = role == TextureRole::Reflectance ? encoding : TextureEncoding::Linear;
    if (role != TextureRole::Reflectance && encoding == TextureEncoding::Srgb)
        failInput(where, "texture '{}': a {} map is data and is read linearly; remove \"encoding\"", name,
                  roleName(role));
    std::vector<float> rgb = readRgb(in, name, e, where, t.width, t.height, wasFloat);
    t.channels = 3;
    if (role == TextureRole::Reflectance) {
        t.kind = Texture::Kind::Rgb;
        t.texels = std::move(rgb);
        checkReflectance(t, where);
        return t;
    }
    for (size_t i = 0; i < rgb.size(); ++i)
        if (!std::isfinite(rgb[i]))
            failInput(where, "texture '{}': texel ({}, {}) is not finite", name, (i / 3) % t.width, (i / 3) / t.width);
    if (role == TextureRole::Scalar) {
        t.kind = Texture::Kind::Scalar;
        t.channels = 1;
        t.texels.resize(size_t(t.width) * t.height);
        for (size_t p = 0; p < t.texels.size(); ++p) {
            t.texels[p] = rgb[p * 3];  // the first (or only) channel
            if (!(t.texels[p] >= 0.0f))
                failInput(where, "texture '{}': texel ({}, {}) is {:g}; a {} map's values must be ≥ 0", name,
                          p % t.width, p / t.width, t.texels[p], roleName(role));
        }
        return t;
    }
    t.kind = Texture::Kind::Normal;
    if (role == TextureRole::Height) {
        std::vector<float> h(size_t(t.width) * t.height);
        for (size_t p = 0; p < h.size(); ++p) h[p] = rgb[p * 3];  // the first (or only) channel
        t.texels = heightToNormals(h, t.width, t.height, bumpScale);
        return t;
    }
    // Normal map: stored as (n + 1)/2; decoded and renormalized here, so that the renderers only
    // interpolate and renormalize. A texel that decodes to (almost) zero is the unperturbed normal.
    t.texels.resize(rgb.size());
    for (size_t p = 0; p < rgb.size(); p += 3) {
        double x = 2.0 * rgb[p] - 1.0, y = 2.0 * rgb[p + 1] - 1.0, z = 2.0 * rgb[p + 2] - 1.0;
        double len = std::sqrt(x * x + y * y + z * z);
        if (!(len > 1e-6)) x = 0, y = 0, z = 1, len = 1;
        t.texels[p] = float(x / len);
        t.texels[p + 1] = float(y / len);
        t.texels[p + 2] = float(z / len);
    }
    return t;
}

}  // namespace

std::vector<float> heightToNormals(const std::vector<float>& h, int w, int ht, double scale) {
    std::vector<float> n(size_t(w) * ht * 3);
    auto at = [&](int x, int y) { return double(h[size_t((y + ht) % ht) * w + size_t((x + w) % w)]); };
    for (int y = 0; y < ht; ++y)
        for (int x = 0; x < w; ++x) {
            double dx = 0.5 * (at(x + 1, y) - at(x - 1, y));
            double dyUp = 0.5 * (at(x, y - 1) - at(x, y + 1));  // row 0 is the top: up is −y
            double nx = -scale * dx, ny = -scale * dyUp, nz = 1.0;
            double len = std::sqrt(nx * nx + ny * ny + nz * nz);
            float* o = &n[(size_t(y) * w + x) * 3];
            o[0] = float(nx / len);
            o[1] = float(ny / len);
            o[2] = float(nz / len);
        }
    return n;
}

uint64_t textureMemoryLimit() { return std::min(uint64_t(8) << 30, decodedImageLimitBytes()); }

Texture loadTexture(const fs::path& path, TextureRole role, TextureEncoding encoding, double bumpScale,
                    const Where& where, const Grid* grid) {
    requireRegularFile(path, where, "texture file");

    // A spectral EXR is recognised by its channels, HDF5 and ENVI cubes by their signatures;
    // anything else is an RGB image.
    const std::optional<CubeFormat> format = cubeFormatOf(path);
    bool spectral = format && *format != CubeFormat::Exr;
    if (spectral && role != TextureRole::Reflectance)
        failInput(where, "texture '{}' is a spectral {} cube; a {} map is an image", path.string(),
                  cubeFormatName(*format), roleName(role));
    const ImageHeaderCheck check = textureHeaderCheck(path.string(), role, grid, where);
    if (role == TextureRole::Reflectance && imageSignature(path) == "openexr") {
        ExrHeader h;
        try {
            h = readExrHeader(path, Where{path.string()});
        } catch (const Error& e) {
            if (e.code() != ExitCode::BadInput) throw;
            failInput(where, "texture '{}' is not a readable image: {}", path.string(), e.message());
        }
        spectral = hasSpectralChannels(h.channels);
    }
    if (spectral) {
        if (encoding == TextureEncoding::Srgb)
            failInput(where, "texture '{}' is spectral; \"encoding\": \"srgb\" applies to RGB images only",
                      path.string());
        return readSpectral(path, where, check);
    }
    return imageTexture(readTextureImage(path, where, check), path.string(), role, encoding, bumpScale, where);
}

Texture loadTexture(const EncodedImage& image, TextureRole role, TextureEncoding encoding, double bumpScale,
                    const Where& where, const Grid* grid) {
    // glTF embeds PNG or JPEG (its core image formats); tell them by their signatures.
    const auto& b = image.bytes;
    const bool png = b.size() >= 8 && std::memcmp(b.data(), "\x89PNG\r\n\x1a\n", 8) == 0;
    const bool jpeg = b.size() >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff;
    if (!png && !jpeg) failInput(where, "texture '{}' is neither a PNG nor a JPEG image (glTF's image formats)", image.name);
    RasterImage decoded;
    try {
        decoded = readRasterImage(b, image.name, Where{image.name}, textureHeaderCheck(image.name, role, grid, where));
    } catch (const Error& e) {
        if (e.code() != ExitCode::BadInput || isAt(e, where)) throw;
        failInput(where, "texture '{}' is not a readable image: {}", image.name, withoutPrefix(e.message()));
    }
    return imageTexture(decoded, image.name, role, encoding, bumpScale, where);
}

}  // namespace metamer
