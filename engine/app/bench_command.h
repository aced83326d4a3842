// `metamer bench SCENE`: the speed/accuracy sweep of the representation modes and spectral steps
// (bench/). Registered on the main CLI11 app by main.cpp; errors are thrown as metamer::Error and
// mapped to exit codes there. docs/speed-vs-accuracy.md.
// Tests: engine/bench/bench_cli_test.cpp (the verb as a user runs it).
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace metamer {

struct BenchArgs {
    std::string scene;
    std::vector<std::string> modes;  // --modes, comma-separated; empty = the defaults
    std::vector<std::string> steps;  // --steps, comma-separated nm; empty = the defaults
    int frames = 5;
    std::string size;                // --size WxH; empty = the scene's camera
    std::string out = "out";
    std::vector<std::string> overrides;
    std::string device;              // also METAMER_DEVICE
    bool validation = false;
    bool quiet = false;              // no progress lines
};

// Adds the `bench` subcommand to `app`, filling `args` when parsed.
CLI::App* addBenchCommand(CLI::App& app, BenchArgs& args);

// Runs the sweep, writes DIR/<scene>.bench.csv, .json and .png, prints the table; returns 0, or 1
// when the validation layers reported errors. Bad flags throw an input Error naming the flag.
int runBenchCommand(const BenchArgs& args);

}  // namespace metamer
