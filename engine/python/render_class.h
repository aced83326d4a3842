// metamer.Render, the result of metamer.render: what RenderJob::capture kept in memory and the
// job's report. Its arrays are read-only numpy views of its own memory; save() writes the CLI's
// files from them; it pickles (its arrays and report, not the loaded scene). compare and capture
// take one as a cube (python/compare, python/capture).
// Tests: tests/python/test_module.py (attributes, views, save against the CLI, pickling).
#pragma once

#include "render/render_job.h"

#include <optional>
#include <string>
#include <vector>

namespace metamer::python {

// The Python result of metamer.render: the captured arrays and the job's report.
struct Render {
    CapturedRender captured;
    RenderJobResult result;
    bool spectral = true;
    std::vector<std::string> channelNames;  // non-spectral modes: the mode's channels
    int bits = 8;
    std::optional<std::vector<std::string>> responseChannels;  // the detector's, when there is a display path
    std::optional<std::string> responseUnits;
    bool unpickled = false;  // made by pickle from another Render: its arrays and report, not its scene
};

}  // namespace metamer::python
