// The bad-input corpus (tests/bad-inputs/): every malformed scene, spectrum file, mesh and
// command-line value must end `metamer render` with exit status 2, one "metamer: " line naming the
// file and the key (or line), and no output — on the GPU and on the CPU backend, and never with
// a crash. The cases run in parallel: each is a process start and a scene load.
#include "render/render_job.h"
#include "support/cli.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using namespace metamer;

namespace {

const fs::path kCorpus = fs::path(METAMER_SOURCE_DIR) / "tests" / "bad-inputs";

struct Case {
    std::string file, expected, args;
    int line = 0;  // in expected.txt
};

std::vector<Case> readManifest() {
    std::ifstream in(kCorpus / "expected.txt");
    std::vector<Case> cases;
    std::string text;
    for (int line = 1; std::getline(in, text); ++line) {
        if (text.empty() || text[0] == '#') continue;
        std::vector<std::string> fields;
        std::stringstream ss(text);
        for (std::string f; std::getline(ss, f, '\t');) fields.push_back(f);
        Case c;
        c.line = line;
        c.file = fields.at(0);
        c.expected = fields.size() > 1 ? fields[1] : "";
        c.args = fields.size() > 2 ? fields[2] : "";
        for (size_t at; (at = c.args.find("{dir}")) != std::string::npos;) c.args.replace(at, 5, kCorpus.string());
        cases.push_back(c);
    }
    return cases;
}

// `metamer render ARGS` in the corpus folder, so that messages name the file as given; the
// timeout turns a case that unexpectedly starts rendering a huge image into a failure (status 124)
// instead of a hung suite. Only stderr is kept: the cases' messages.
test::CliRun runMetamer(const std::string& args) {
    test::CliOptions o;
    o.dir = kCorpus.string();
    o.timeoutSeconds = 120;
    o.stderrOnly = true;
    return test::runMetamer("render " + args, o);
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream ss(text);
    for (std::string l; std::getline(ss, l);) out.push_back(l);
    return out;
}

bool startsWith(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

fs::path scratch(const std::string& name) {
    fs::path d = fs::temp_directory_path() / ("metamer-bad-inputs-" + std::to_string(::getpid())) / name;
    fs::remove_all(d);
    return d;
}

// Runs jobs(i) for i in [0, n) on a few threads; each job only starts a process and waits.
template <typename F>
void inParallel(size_t n, F job) {
    std::atomic<size_t> next{0};
    unsigned threads = std::max(4u, 2 * std::thread::hardware_concurrency());
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < std::min<size_t>(threads, n); ++t)
        pool.emplace_back([&] {
            for (size_t i; (i = next++) < n;) job(i);
        });
    for (auto& t : pool) t.join();
}

}  // namespace

TEST(BadInputs, TheBaseSceneIsValid) {
    // Every case is this scene with one thing wrong; it must render, or the cases prove nothing.
    for (const char* backend : {"gpu", "cpu"}) {
        fs::path out = scratch(std::string("valid-") + backend);
        test::CliRun r = runMetamer("valid-base.json --out " + out.string() + " --backend " + backend);
        EXPECT_EQ(r.code, 0) << backend << ": " << r.output;
        EXPECT_TRUE(fs::exists(out / "valid-base.exr")) << backend;
    }
}

TEST(BadInputs, EveryCaseFileIsInTheManifest) {
    std::set<std::string> listed;
    for (const auto& c : readManifest()) {
        listed.insert(c.file);
        EXPECT_TRUE(fs::exists(kCorpus / c.file)) << "expected.txt:" << c.line << ": no file " << c.file;
        EXPECT_FALSE(c.expected.empty()) << "expected.txt:" << c.line << ": no expected text";
    }
    for (const auto& e : fs::directory_iterator(kCorpus))
        if (e.path().extension() == ".json")
            EXPECT_TRUE(listed.count(e.path().filename().string())) << e.path().filename() << " is not in expected.txt";
    EXPECT_GE(readManifest().size(), 40u);
}

// Every case on one backend: exit status 2, one error line naming the file and the expected key or
// line, printable, and nothing written.
void checkCorpus(const std::string& backend) {
    std::vector<Case> cases = readManifest();
    ASSERT_FALSE(cases.empty());
    struct Result {
        test::CliRun run;
        fs::path out;
    };
    std::vector<Result> results(cases.size());
    inParallel(results.size(), [&](size_t i) {
        const Case& c = cases[i];
        results[i].out = scratch(std::to_string(c.line) + "-" + backend);
        results[i].run = runMetamer(c.file + " --out " + results[i].out.string() + " " + c.args + " --backend " + backend);
    });
    for (size_t i = 0; i < results.size(); ++i) {
        const Case& c = cases[i];
        const test::CliRun& r = results[i].run;
        std::string what = "expected.txt:" + std::to_string(c.line) + " " + c.file + " " + c.args + " --backend " +
                           backend + "\n" + r.output;
        EXPECT_EQ(r.code, 2) << what << (r.code > 128 ? "(killed by a signal: a crash)" : "");
        // One error line, the last; anything before it is a warning.
        std::vector<std::string> ls = lines(r.output);
        size_t errors = std::count_if(ls.begin(), ls.end(), [](const std::string& l) { return startsWith(l, "metamer: "); });
        EXPECT_EQ(errors, 1u) << what;
        if (ls.empty()) continue;
        for (size_t k = 0; k + 1 < ls.size(); ++k) EXPECT_TRUE(startsWith(ls[k], "warning: ")) << what;
        const std::string& error = ls.back();
        EXPECT_TRUE(startsWith(error, "metamer: ")) << what;
        EXPECT_NE(error.find(c.expected), std::string::npos) << "missing '" << c.expected << "'\n" << what;
        // The file is named, except in errors about a flag itself.
        if (!startsWith(c.expected, "--")) EXPECT_TRUE(startsWith(error, "metamer: " + c.file)) << what;
        // Printable: no control characters (a binary file's bytes are written as \xNN).
        EXPECT_TRUE(std::none_of(error.begin(), error.end(), [](char ch) { return ch >= 0 && ch < 0x20; })) << what;
        // Nothing written: the output folder absent or empty.
        std::error_code ec;
        EXPECT_TRUE(!fs::exists(results[i].out) || fs::is_empty(results[i].out, ec)) << what;
        fs::remove_all(results[i].out);
    }
}

TEST(BadInputs, EachFailsCleanlyOnTheGpuBackend) { checkCorpus("gpu"); }

TEST(BadInputs, EachFailsCleanlyOnTheCpuBackend) { checkCorpus("cpu"); }

TEST(BadInputs, RenderMemoryEstimate) {
    // The cube: W·H·bands floats.
    RenderMemory cpu = estimateRenderMemory(512, 256, 89, 1, Backend::Cpu, false);
    EXPECT_EQ(cpu.cube, 512ull * 256 * 89 * 4);
    EXPECT_EQ(cpu.target, 0u);
    EXPECT_EQ(cpu.display, 0u);
    // The GPU target: 23 RGBA32F layers at the supersampled size, a readback copy and a depth buffer.
    RenderMemory gpu = estimateRenderMemory(512, 256, 89, 2, Backend::Gpu, true);
    uint64_t samples = 512ull * 256 * 4;
    EXPECT_EQ(gpu.target, 2 * samples * 23 * 16 + samples * 4);
    EXPECT_GT(gpu.display, cpu.display);
    EXPECT_EQ(gpu.total(), gpu.cube + gpu.target + gpu.display);
    // No overflow at the largest sizes the loader accepts: 16384² on a 0.5 nm grid over 200–2500 nm.
    RenderMemory huge = estimateRenderMemory(16384, 16384, 4601, 4, Backend::Gpu, true);
    EXPECT_EQ(huge.cube, 16384ull * 16384 * 4601 * 4);
    EXPECT_GT(huge.total(), huge.cube);
    EXPECT_GT(huge.total(), kMaxRenderMemory);
    // What the bundled scenes need is far below the limit; the corpus's absurd sizes far above.
    EXPECT_LT(estimateRenderMemory(1024, 1024, 89, 4, Backend::Gpu, true).total(), kMaxRenderMemory / 4);
    EXPECT_GT(estimateRenderMemory(16384, 16384, 89, 1, Backend::Cpu, true).total(), kMaxRenderMemory);
    EXPECT_NE(gpu.describe().find("GiB (cube "), std::string::npos) << gpu.describe();
}
