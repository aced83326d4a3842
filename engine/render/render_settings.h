// The render options a user types, as typed, declared once for every front end: `metamer
// render`'s flags, the ones `preview`, `bench` and `batch` share with it (app/render_flags.h) and
// the Python module's keyword arguments where they overlap (engine/python). One help text each
// (renderSettingHelp); applyRenderSettings checks and converts them into a RenderJob.
// Tests: tests/cli_test.cpp, tests/python/test_module.py.
#pragma once

#include "render/render_job_spec.h"

#include <functional>
#include <string>
#include <vector>

namespace metamer {

struct RenderSettings {
    std::vector<std::string> overrides;  // set: KEY=VALUE
    std::string grid, resample;          // "" = the scene's
    std::string mode = "full";
    std::string detector, adapt, display, integration, xyz;  // "" = the scene's output block, else the default
    int bits = 0;                                             // 0 = the scene's, else 8
    int ssaa = 1;
    std::string backend = "gpu", readback = "auto";
    bool half = false;
    std::string compression = "piz";
    bool strictCoverage = false;
    double memoryBudgetMiB = 0;  // 0 = a quarter of the machine's memory
    std::vector<std::string> write, format;  // empty = the scene's, else the default
    bool noPng = false;
    int frames = 1;
    bool validation = false;
    std::string device;
    bool verbose = false;
    bool allowOutsidePaths = false;
};

// The help of option `name` (its CLI spelling without "--": "grid", "memory-budget"), the same text
// in every front end; a runtime error for a name it does not know.
const char* renderSettingHelp(const std::string& name);

// Fills `job` from `s`. Input errors name the option as the front end spells it: `spell("grid")`
// is "--grid" on the command line, "grid" in Python.
void applyRenderSettings(const RenderSettings& s, RenderJob& job,
                         const std::function<std::string(const std::string&)>& spell);

}  // namespace metamer
