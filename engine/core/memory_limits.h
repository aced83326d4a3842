// How much memory this machine gives the process, and the limits derived from it: what an image
// may take once decoded (checked from its header, before any pixel is read), and the default
// memory budget of a render (render/strip_render.h). docs/numerics.md, "Bad input", says why a
// quarter. Tests: engine/core/memory_limits_test.cpp.
#pragma once

#include "core/error.h"

#include <cstdint>
#include <string>

namespace metamer {

// Physical memory, or the cgroup's memory limit (v2 memory.max, v1 memory.limit_in_bytes) when
// that is lower; 8 GiB when neither can be read.
uint64_t machineMemoryBytes();

// The most an image or cube read from a file may take decoded (its pixels as float32 plus the
// decoder's own buffer): a quarter of machineMemoryBytes().
uint64_t decodedImageLimitBytes();

// That an image of width × height × channels values, decoded to `bytesPerValue` each plus
// `decoderBytes` of the decoder's own, fits decodedImageLimitBytes(); otherwise an input error at
// `where` that says the size, the limit and the machine's memory. Called from a file's header,
// before any pixel is decoded.
void requireDecodableSize(uint64_t width, uint64_t height, uint64_t channels, uint64_t bytesPerValue,
                          uint64_t decoderBytes, const Where& where, const std::string& what);

// "5.8 GiB", "300.0 MiB": a size for messages.
std::string memorySize(uint64_t bytes);

}  // namespace metamer
