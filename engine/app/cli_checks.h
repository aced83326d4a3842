// Checks every command line gets after CLI11 has parsed it, in one place rather than per flag
// (issue 19, class 3): no option value may be an empty string (`--grid ''` used to mean the
// default, `--out ''` the scene's own folder), and a number must be finite (`--memory-budget nan`
// used to pass CLI11's positive-number check, which NaN does not fail), and an unsigned integer
// (`--seed`, `--frame`) must be written as one that fits 64 bits (issue 51, class 3: CLI11 read
// `-1` and `2⁶⁴` as 2⁶⁴ − 1, silently). And the verb: an unknown
// one is an error with the nearest verb, not CLI11's generic complaint or, with --help, the
// top-level help and exit 0; a mistyped option, likewise, gets the nearest option. Errors name the
// option as the user typed it (`--grid`).
// Tests: tests/cli_test.cpp (CliChecks.*).
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace metamer {

// Before parsing: argv[1], when it is not an option, must be one of `app`'s subcommands.
void checkVerb(const CLI::App& app, int argc, char** argv);

// After parsing: every value given to an option of `app` or of a subcommand that was used.
void checkParsedValues(const CLI::App& app);

// After CLI11's ExtrasError: the first argument the command did not expect, as an input error —
// a mistyped option with the nearest of the command's options (`--outptu`: did you mean
// --output?), anything else with what the command takes.
[[noreturn]] void failUnexpectedArguments(const CLI::App& app);

// A validator for a number > 0 whose message says so in words (CLI11's PositiveNumber prints the
// range as "0.000000 to 1.797…e308").
CLI::Validator positiveNumber(const std::string& unit = "");
// The same for ≥ 0.
CLI::Validator nonNegativeNumber();
// An output folder: missing (it will be created) or a folder, not a file or a device (`--out
// /dev/full` used to fail only after the render, when the first file was opened).
CLI::Validator outputFolder();

}  // namespace metamer
