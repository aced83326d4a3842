// Any spectral cube file, whatever its format: OpenEXR in the spectral layout (io/spectral_exr.h),
// HDF5 (io/hdf5_cube.h) or ENVI (io/envi_cube.h), told apart by their contents, not their names.
// Tests: engine/io/spectral_image_test.cpp.
#pragma once

#include "io/spectral_exr.h"

#include <filesystem>
#include <optional>

namespace metamer {

enum class CubeFormat { Exr, Hdf5, Envi };
const char* cubeFormatName(CubeFormat format);  // "OpenEXR", "HDF5", "ENVI"

// The format by signature: the OpenEXR magic number 0x762f3101, the HDF5 signature
// "\x89HDF\r\n\x1a\n" at offset 0 or after a user block (512, 1024, 2048, ...), an ENVI header (a file starting with "ENVI"), or ENVI data (a
// .img, .raw or .dat whose <stem>.hdr or <name>.hdr starts with "ENVI"). Nothing for anything else,
// including a path that is missing or not a regular file. Never throws.
std::optional<CubeFormat> cubeFormatOf(const std::filesystem::path& path);

// Reads a cube with readSpectralExrImage, readHdf5Cube or readEnviCube as cubeFormatOf says;
// `check` sees its size from the header first (spectral_exr.h). Input errors name the file: not
// found, not a regular file, none of the three formats, too large to read.
SpectralImage readSpectralImage(const std::filesystem::path& path, const CubeHeaderCheck& check = {});

}  // namespace metamer
