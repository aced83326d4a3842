// `metamer bench` as a user runs it: flags are checked before the sweep, errors name the flag.
#include "support/cli.h"

#include <gtest/gtest.h>

#include <string>

namespace {

using CliResult = metamer::test::CliRun;

CliResult runBenchCli(const std::string& args) {
    return metamer::test::runMetamer("bench " METAMER_SOURCE_DIR "/scenes/metamers.json " + args);
}

bool has(const CliResult& r, const std::string& text) { return r.output.find(text) != std::string::npos; }

}  // namespace

TEST(BenchCli, ABadModeIsAnInputErrorNamingModes) {
    CliResult r = runBenchCli("--modes full,rbg --out /nonexistent-bench-dir");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_TRUE(has(r, "--modes")) << r.output;
    EXPECT_TRUE(has(r, "'rbg'")) << r.output;
    EXPECT_TRUE(has(r, "did you mean 'rgb'")) << r.output;
}

TEST(BenchCli, BadStepsAndSizesAreInputErrorsNamingTheFlag) {
    CliResult steps = runBenchCli("--steps 5,0.1");
    EXPECT_EQ(steps.code, 2) << steps.output;
    EXPECT_TRUE(has(steps, "--steps")) << steps.output;
    CliResult word = runBenchCli("--steps 5,fine");
    EXPECT_EQ(word.code, 2) << word.output;
    EXPECT_TRUE(has(word, "'fine'")) << word.output;
    CliResult size = runBenchCli("--size 256");
    EXPECT_EQ(size.code, 2) << size.output;
    EXPECT_TRUE(has(size, "--size")) << size.output;
}
