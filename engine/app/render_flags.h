// The render flags as CLI11 options, declared once from render/render_settings.h (one help text
// each): `metamer render` takes every group, `preview` the ones a window uses, `bench` and `batch`
// single flags for the values they keep themselves.
// Tests: tests/cli_test.cpp, tests/preview_test.sh.
#pragma once

#include "render/render_settings.h"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace metamer {

enum RenderFlagGroup : unsigned {
    kSceneFlags = 1,     // --set, --allow-outside-paths
    kSpectralFlags = 2,  // --grid, --resample, --mode
    kDisplayFlags = 4,   // --detector, --adapt, --display, --bits, --integration
    kSamplingFlags = 8,  // --ssaa
    kDeviceFlags = 16,   // --validation, --device, --verbose
    kFileFlags = 32,     // --backend, --readback, --half, --compression, --strict-coverage, --memory-budget,
                         // --xyz, --write, --format, --no-png, --frames: what only `render` does
    kAllRenderFlags = 63,
};

// Adds the groups' flags to `c`, filling `s` when parsed.
void addRenderFlags(CLI::App* c, RenderSettings& s, unsigned groups);

// One flag with its shared help, for a command that keeps the value itself.
CLI::Option* addRenderFlag(CLI::App* c, const std::string& name, std::string& value);
CLI::Option* addRenderFlag(CLI::App* c, const std::string& name, std::vector<std::string>& value);
CLI::Option* addRenderFlag(CLI::App* c, const std::string& name, bool& value);

}  // namespace metamer
