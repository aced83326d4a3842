// `metamer compare A B`: A against the reference B (compare/), as a user or a regression test
// runs it. Registered on the main CLI11 app by main.cpp; errors are thrown as metamer::Error and
// mapped to exit codes there. docs/compare.md.
// Tests: engine/compare/compare_cli_test.cpp.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace metamer {

struct CompareArgs {
    std::string a, b;               // test image, reference
    std::string tolerance, heatmap, json, mask;
    bool resample = false;
    std::string detector, adapt, display;  // ΔE2000 setup; empty = default (cie1931, bradford, srgb)
    bool noDeltaE = false;
    double pixelThreshold = -1.0, relativeFloor = -1.0;  // < 0: from the tolerance file or the defaults
    bool verbose = false;
    bool quiet = false;             // one line of statistics and the verdict
};

// Adds the `compare` subcommand to `app`, filling `args` when parsed.
CLI::App* addCompareCommand(CLI::App& app, CompareArgs& args);

// Runs it: prints the summary, writes the requested files, and returns 0 (no tolerance, or
// within it) or 1 (outside the tolerance). Unusable input throws an input Error (exit 2).
int runCompare(const CompareArgs& args);

}  // namespace metamer
