// `metamer preview SCENE`: the interactive spectral preview window (engine/preview,
// docs/preview.md). Registered on the main CLI11 app by main.cpp; errors are thrown as
// metamer::Error and mapped to exit codes there (no display: exit 4).
// Tests: tests/preview_test.sh (under Xvfb), engine/preview/preview_settings_test.cpp.
#pragma once

#include "render/render_settings.h"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace metamer {

struct PreviewArgs {
    std::string scene;
    RenderSettings render;  // the flags it shares with `metamer render` (app/render_flags.h)
    std::vector<std::string> split;
    int frames = 0;
    std::string screenshot, windowScreenshot, out = "out", probe, pin;
    bool save = false, noWatch = false;
};

// Adds the `preview` subcommand to `app`, filling `args` when parsed.
CLI::App* addPreviewCommand(CLI::App& app, PreviewArgs& args);

// Opens the window (until it is closed, or for --frames N frames), prints the figures and what
// was written; returns 0, or 1 when the validation layers reported errors.
int runPreviewCommand(const PreviewArgs& args);

}  // namespace metamer
