// `metamer batch` as a user runs it: exit codes, the listing, a batch killed mid-run and resumed
// (nothing partial left, only the missing jobs rendered), and shards run side by side with
// `xargs -P` gathered into the same index as one whole run (docs/batch.md).
#include "support/cli.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace fs = std::filesystem;
using namespace metamer;

namespace {

fs::path freshDir(const std::string& name) {
    fs::path d = fs::temp_directory_path() / fmt::format("metamer-batch-cli-{}-{}", ::getpid(), name);
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

test::CliRun shell(const std::string& cmd) {
    test::CliRun r;
    FILE* p = popen((cmd + " 2>&1").c_str(), "r");
    if (!p) return r;
    char buf[4096];
    while (size_t n = fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
    const int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    return r;
}

// A sweep over the CLI tests' small scene: `lights` light spectra × `detectors`.
fs::path writeSweep(const fs::path& dir, const std::string& render, int lights = 3) {
    const char* spectra[] = {"illuminants/D65", "illuminants/A", "illuminants/FL2", "illuminants/D50",
                             "illuminants/E",   "illuminants/FL11", "illuminants/FL1", "illuminants/FL3"};
    std::string values;
    for (int i = 0; i < lights; ++i) values += fmt::format("{}\"{}\"", i ? ", " : "", spectra[i]);
    const fs::path p = dir / "sweep.json";
    std::ofstream(p) << fmt::format(R"({{
  "scenes": ["{}/tests/data/cli/small.json"],
  "render": {},
  "axes": [{{"name": "light", "set": "lights.1.spectrum", "values": [{}]}},
           {{"render": "detector", "values": ["cie1931", "cie1964"]}}]
}})",
                                    METAMER_SOURCE_DIR, render, values);
    return p;
}

// Files under `dir` named `name` exactly (a record being written is ".job.json.tmp-…", not counted),
// or, with `part`, whose name contains it.
size_t countFiles(const fs::path& dir, const std::string& name, bool part = false) {
    size_t n = 0;
    std::error_code ec;
    for (const auto& e : fs::recursive_directory_iterator(dir, ec)) {
        const std::string f = e.path().filename().string();
        n += part ? f.find(name) != std::string::npos : f == name;
    }
    return n;
}

std::vector<std::string> lines(const fs::path& file) {
    std::ifstream in(file);
    std::vector<std::string> v;
    for (std::string l; std::getline(in, l);) v.push_back(l);
    return v;
}

}  // namespace

TEST(BatchCli, RendersListsSkipsAndSaysWhatFailedInItsExitCode) {
    const fs::path dir = freshDir("basic");
    const fs::path sweep = writeSweep(dir, R"({"write": "png,xyz", "size": "24x16"})");
    const std::string out = (dir / "out").string();
    test::CliRun r = test::runMetamer("batch " + sweep.string() + " --out " + out + " --validation");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("6 jobs: 6 rendered, 0 skipped (done before), 0 failed"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("[6/6] small-"), std::string::npos) << r.output;  // a line per job (not a terminal)
    EXPECT_EQ(lines(dir / "out" / "index.csv").size(), 7u);
    r = test::runMetamer("batch " + sweep.string() + " --out " + out + " -q");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("0 rendered, 6 skipped"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("[1/6]"), std::string::npos) << r.output;
    r = test::runMetamer("batch " + sweep.string() + " --out " + out + " --list");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\t'), 12) << r.output;
    EXPECT_NE(r.output.find("\tdone\tscenes.0 × light=illuminants/FL2, detector=cie1964"), std::string::npos)
        << r.output;

    // A bad sweep: exit 2, the file and key named, nothing rendered.
    std::ofstream(dir / "bad.json") << R"({"scenes": ["x.json"], "axes": [{"render": "detektor", "values": ["a"]}]})";
    r = test::runMetamer("batch " + (dir / "bad.json").string() + " --out " + (dir / "bad-out").string());
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("bad.json: axes.0.render: unknown render setting 'detektor' (did you mean 'detector'?)"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(dir / "bad-out"));
    // A job whose scene cannot load: exit 2 before the first render.
    std::ofstream(dir / "bad-key.json") << fmt::format(
        R"({{"scenes": ["{}/tests/data/cli/small.json"], "axes": [{{"set": "lights.1.spectrum", "values": ["illuminants/D65", "illuminants/nope"]}}]}})",
        METAMER_SOURCE_DIR);
    r = test::runMetamer("batch " + (dir / "bad-key.json").string() + " --out " + (dir / "bad-out").string());
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("job 2 of 2"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("lights.1.spectrum"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "bad-out"));
    // A job that fails while rendering (its PNG cannot be put in place: a folder is in the way): the
    // others render, exit 1, the failure named; the next run leaves it failed, --retry-failed retries.
    const fs::path failOut = dir / "fails-out";
    r = test::runMetamer("batch " + sweep.string() + " --out " + failOut.string() + " --list");
    ASSERT_EQ(r.code, 0) << r.output;
    const size_t at = r.output.find("small-");  // the first job's line (warnings come first)
    ASSERT_NE(at, std::string::npos) << r.output;
    const std::string id = r.output.substr(at, r.output.find('\t', at) - at);
    fs::create_directories(failOut / id / "small.png" / "in-the-way");
    r = test::runMetamer("batch " + sweep.string() + " --out " + failOut.string() + " -q");
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("5 rendered, 0 skipped (done before), 1 failed"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("failed: " + id + ": "), std::string::npos) << r.output;
    r = test::runMetamer("batch " + sweep.string() + " --out " + failOut.string() + " -q");
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("0 rendered, 5 skipped (done before), 1 failed"), std::string::npos) << r.output;
    fs::remove_all(failOut / id / "small.png");
    r = test::runMetamer("batch " + sweep.string() + " --out " + failOut.string() + " -q --retry-failed");
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("1 rendered, 5 skipped (done before), 0 failed"), std::string::npos) << r.output;
}

TEST(BatchCli, AKilledBatchResumesWithNothingPartialLeftAndRendersOnlyTheMissingJobs) {
    for (const char* signal : {"KILL", "TERM"}) {
        SCOPED_TRACE(signal);
        const fs::path dir = freshDir(std::string("killed-") + signal);
        // 16 jobs of a cube and a PNG at 256×192 × 89 bands: long enough to be killed mid-way.
        const fs::path sweep = writeSweep(dir, R"({"write": "cube,png", "size": "256x192"})", 8);
        const fs::path out = dir / "out";
        const std::string cmd = std::string(METAMER_BINARY) + " batch " + sweep.string() + " --out " + out.string() +
                                " -q > " + (dir / "log").string() + " 2>&1";
        const pid_t pid = fork();
        ASSERT_GE(pid, 0);
        if (pid == 0) {
            execl("/bin/sh", "sh", "-c", ("exec " + cmd).c_str(), (char*)nullptr);
            _exit(127);
        }
        // Kill it once three jobs are recorded (or after 60 s).
        const auto start = std::chrono::steady_clock::now();
        while (countFiles(out, "job.json") < 3 && std::chrono::steady_clock::now() - start < std::chrono::seconds(60))
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        ::kill(pid, std::string(signal) == "KILL" ? SIGKILL : SIGTERM);
        int status = 0;
        ::waitpid(pid, &status, 0);
        const size_t recorded = countFiles(out, "job.json");
        ASSERT_GE(recorded, 3u);
        ASSERT_LT(recorded, 16u) << "the batch finished before it could be killed";
        if (std::string(signal) == "TERM") EXPECT_EQ(countFiles(out, ".tmp-", true), 0u);  // the handler removed them
        const test::CliRun r = test::runMetamer("batch " + sweep.string() + " --out " + out.string() + " -q");
        ASSERT_EQ(r.code, 0) << r.output;
        EXPECT_NE(r.output.find(fmt::format("{} rendered, {} skipped", 16 - recorded, recorded)), std::string::npos)
            << r.output;
        EXPECT_EQ(countFiles(out, ".tmp-", true), 0u);
        EXPECT_EQ(countFiles(out, "job.json"), 16u);
        EXPECT_EQ(countFiles(out, "small.exr"), 16u);
    }
}

TEST(BatchCli, ShardsUnderXargsGiveTheSameDatasetAsOneRun) {
    const fs::path dir = freshDir("xargs");
    const fs::path sweep = writeSweep(dir, R"({"write": "png,xyz", "size": "24x16"})", 4);
    test::CliRun whole = test::runMetamer("batch " + sweep.string() + " --out " + (dir / "whole").string() + " -q");
    ASSERT_EQ(whole.code, 0) << whole.output;
    // docs/batch.md, "One workstation": the shards side by side, then the index.
    const std::string m = METAMER_BINARY;
    test::CliRun r = shell("seq 0 3 | xargs -P 2 -I{} " + m + " batch " + sweep.string() + " --shard {}/4 --out " +
                           (dir / "sharded").string() + " -q && " + m + " batch --index " + (dir / "sharded").string());
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("index: 8 job records (8 done, 0 failed)"), std::string::npos) << r.output;
    // The index loads in one line with pandas, CSV and JSON alike (the venv's, ci/setup.sh).
    test::CliRun pandas = shell(
        std::string(METAMER_SOURCE_DIR) + "/.venv/bin/python -W ignore -c \"import pandas as pd, sys; d = pd.read_csv(sys.argv[1] + '/index.csv'); "
        "j = pd.read_json(sys.argv[1] + '/index.json'); "
        "assert len(d) == 8 and (d.status == 'done').all() and list(d.id) == list(j.id), d; "
        "assert set(d['set:lights.1.spectrum']) == {'illuminants/D65', 'illuminants/A', 'illuminants/FL2', 'illuminants/D50'}; "
        "print('pandas', d.shape, j.shape, d.groupby('detector').ms_job.median().size)\" " +
        (dir / "sharded").string());
    EXPECT_EQ(pandas.code, 0) << pandas.output;
    EXPECT_NE(pandas.output.find("pandas (8, "), std::string::npos) << pandas.output;
    const std::vector<std::string> a = lines(dir / "whole" / "index.csv"), b = lines(dir / "sharded" / "index.csv");
    ASSERT_EQ(a.size(), 9u);
    ASSERT_EQ(b.size(), 9u);
    EXPECT_EQ(a[0], b[0]);  // the same columns
    // A batch job's files are those `metamer render` writes for the same settings (a batch reuses
    // the device, pipelines and parsed tables of the jobs before).
    {
        const std::string last = a.back().substr(0, a.back().find(','));
        test::CliRun render = test::runMetamer(fmt::format(
            "render {}/tests/data/cli/small.json --out {} --set lights.1.spectrum=illuminants/D50 --set camera.width=24 "
            "--set camera.height=16 --detector cie1964 --write png,xyz",
            METAMER_SOURCE_DIR, (dir / "render").string()));
        ASSERT_EQ(render.code, 0) << render.output;
        for (const char* f : {"small.png", "small.xyz.exr"}) {
            const test::CliRun cmp = shell("cmp " + (dir / "whole" / last / f).string() + " " + (dir / "render" / f).string());
            EXPECT_EQ(cmp.code, 0) << last << "/" << f << " differs from metamer render's: " << cmp.output;
        }
    }
    for (size_t i = 1; i < a.size(); ++i) {
        const std::string id = a[i].substr(0, a[i].find(','));
        EXPECT_EQ(b[i].substr(0, b[i].find(',')), id);  // the same jobs, in sweep order
        for (const char* f : {"small.png", "small.xyz.exr"}) {
            const test::CliRun cmp = shell("cmp " + (dir / "whole" / id / f).string() + " " + (dir / "sharded" / id / f).string());
            EXPECT_EQ(cmp.code, 0) << id << "/" << f << ": " << cmp.output;
        }
    }
}

// A sweep of seeds and exposures through a simulated sensor (docs/sensor.md): each job's folder
// holds its cube and its raw frames; a second run skips them all; an edited sensor file captures
// again (its digest is in the jobs'), and a job's raw equals `metamer capture` of its own cube.
TEST(BatchCli, SweepsSeedsAndExposuresThroughASensor) {
    const fs::path dir = freshDir("sensor");
    fs::copy_file(fs::path(METAMER_SOURCE_DIR) / "spectra/sensors/aps_c_rggb.json", dir / "sensor.json");
    std::ofstream(dir / "sweep.json") << fmt::format(R"({{
  "scenes": ["{}/tests/data/cli/small.json"],
  "render": {{"write": "png", "sensor": "sensor.json", "frames": 2}},
  "axes": [{{"render": "seed", "values": [1, 2]}}, {{"render": "exposure", "values": [0.002, 0.0002]}}]
}})",
                                                     METAMER_SOURCE_DIR);
    const std::string binary = METAMER_BINARY;
    const std::string run = fmt::format("{} batch {} --out {}", binary, (dir / "sweep.json").string(), (dir / "out").string());
    test::CliRun first = shell(run);
    ASSERT_EQ(first.code, 0) << first.output;
    EXPECT_NE(first.output.find("4 rendered"), std::string::npos) << first.output;
    EXPECT_EQ(countFiles(dir / "out", ".raw.0.dng", true), 4u);
    EXPECT_EQ(countFiles(dir / "out", ".raw.1.png", true), 4u);
    EXPECT_EQ(countFiles(dir / "out", ".electrons.exr", true), 4u);
    EXPECT_NE(shell(run).output.find("0 rendered, 4 skipped"), std::string::npos);
    // The index has the sensor settings as columns.
    const std::vector<std::string> index = lines(dir / "out/index.csv");
    ASSERT_EQ(index.size(), 5u);
    EXPECT_NE(index[0].find("exposure"), std::string::npos);
    EXPECT_NE(index[0].find("seed"), std::string::npos);
    // A job's frame 1 equals metamer capture of that job's cube with its seed and exposure.
    fs::path job;
    for (const auto& e : fs::directory_iterator(dir / "out"))
        if (e.is_directory()) {
            std::ifstream in(e.path() / "job.json");
            std::stringstream s;
            s << in.rdbuf();
            if (s.str().find("\"seed\": 2") != std::string::npos && s.str().find("0.0002") != std::string::npos) job = e.path();
        }
    ASSERT_FALSE(job.empty());
    const test::CliRun again = shell(fmt::format("{} capture {} --sensor {} --seed 2 --frame 1 --exposure 0.0002 --out {}", binary,
                                                 (job / "small.exr").string(), (dir / "sensor.json").string(),
                                                 (dir / "direct").string()));
    ASSERT_EQ(again.code, 0) << again.output;
    auto bytes = [](const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    EXPECT_EQ(bytes(job / "small.raw.1.dng"), bytes(dir / "direct/small.raw.dng"));
    // An edited sensor (more read noise) captures every job again.
    std::ifstream in(dir / "sensor.json");
    std::stringstream text;
    text << in.rdbuf();
    std::string edited = text.str();
    edited.replace(edited.find("\"read_noise_e\": 3.0"), 19, "\"read_noise_e\": 4.0");
    std::ofstream(dir / "sensor.json") << edited;
    EXPECT_NE(shell(run).output.find("4 rendered"), std::string::npos);
    fs::remove_all(dir);
}

// Issue 51, class 4: a job whose capture fails (an unlit scene's auto-exposure) puts none of its
// files in place: no cube or PNG without the raw frames they go with, no staging folder left.
TEST(BatchCli, AJobWhoseCaptureFailsWritesNoneOfItsFiles) {
    const fs::path dir = freshDir("sensor-unlit");
    std::ofstream(dir / "sweep.json") << fmt::format(R"({{
  "scenes": ["{}/tests/data/cli/small.json"],
  "set": {{"lights.0.scale": 0, "lights.1.scale": 0, "camera.width": 24, "camera.height": 16}},
  "render": {{"write": "png", "sensor": "aps_c_rggb"}},
  "axes": [{{"set": "lights.2.scale", "values": [0.2, 0]}}]
}})",
                                                     METAMER_SOURCE_DIR);
    const test::CliRun r =
        shell(fmt::format("{} batch {} --out {}", METAMER_BINARY, (dir / "sweep.json").string(), (dir / "out").string()));
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("1 rendered, 0 skipped (done before), 1 failed"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("auto-exposure needs light"), std::string::npos) << r.output;
    size_t lit = 0, unlit = 0;
    for (const auto& e : fs::directory_iterator(dir / "out")) {
        if (!e.is_directory()) continue;
        std::vector<std::string> names;
        for (const auto& f : fs::directory_iterator(e.path())) names.push_back(f.path().filename().string());
        std::sort(names.begin(), names.end());
        if (fs::exists(e.path() / "small.exr")) {
            ++lit;
            EXPECT_EQ(names, (std::vector<std::string>{"job.json", "small.electrons.exr", "small.exr", "small.png",
                                                       "small.raw.dng", "small.raw.json", "small.raw.png",
                                                       "small.raw.srgb.png"}));
        } else {
            ++unlit;
            EXPECT_EQ(names, std::vector<std::string>{"job.json"});  // the failed job's record only
        }
    }
    EXPECT_EQ(lit, 1u);
    EXPECT_EQ(unlit, 1u);
    fs::remove_all(dir);
}

// Issue 30, classes 4 and 5: a sweep with a job given twice is refused by every mode — not only by
// the run that reaches it — and --slurm refuses option values Slurm would read as something else
// (a newline ends sbatch's directives and runs the rest as shell), before writing anything.
TEST(BatchCli, EveryModeRefusesAJobGivenTwiceAndSlurmValuesAreCheckedBeforeAnythingIsWritten) {
    const fs::path dir = freshDir("twice");
    std::ofstream(dir / "twice.json") << fmt::format(
        R"({{"scenes": ["{}/tests/data/cli/small.json"], "axes": [{{"render": "bits", "values": [8, 10, 8]}}]}})",
        METAMER_SOURCE_DIR);
    const std::string out = (dir / "out").string();
    for (const char* mode : {"", "--list", "--dry-run", "--slurm", "--shard 1/2", "--shard 0/2"}) {
        const test::CliRun r =
            test::runMetamer(fmt::format("batch {} --out {} {}", (dir / "twice.json").string(), out, mode));
        EXPECT_EQ(r.code, 2) << mode << r.output;
        EXPECT_NE(r.output.find("twice.json: scenes.0: jobs 1 (scenes.0 × bits=8) and 3 (scenes.0 × bits=8) render "
                                "the same thing"),
                  std::string::npos)
            << mode << r.output;
        EXPECT_FALSE(fs::exists(out)) << mode;
    }

    const fs::path sweep = writeSweep(dir, R"({"size": "8x8"})");
    test::CliRun r = test::runMetamer(fmt::format(
        "batch {} --out {} --slurm --partition \"$(printf 'debug\\necho pwned')\"", sweep.string(), out));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("--partition: expected a partition name"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    r = test::runMetamer(fmt::format("batch {} --out {} --slurm --time '2 hours'", sweep.string(), out));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("--time: expected a time limit as Slurm writes one"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    // 50 tasks asked for 6 jobs: 6 tasks, none empty; other sbatch options passed through; the
    // spectra library that the ids were made with exported by the script itself (issue 31 item 5).
    test::CliOptions env;
    env.env = fmt::format("METAMER_SPECTRA={}/spectra", METAMER_SOURCE_DIR);
    r = test::runMetamer(fmt::format("batch {} --out {} --slurm --tasks 50 --mem 2G --sbatch gres=gpu:1 "
                                     "--sbatch=--account=lab",
                                     sweep.string(), out),
                         env);
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("6 jobs, all valid, in 6 array tasks"), std::string::npos) << r.output;
    const std::vector<std::string> script = lines(fs::path(out) / "slurm" / "array.sbatch");
    ASSERT_GE(script.size(), 12u);
    EXPECT_EQ(script[4], "#SBATCH --gres=gpu:1");
    EXPECT_EQ(script[5], "#SBATCH --account=lab");
    EXPECT_EQ(script[6], "#SBATCH --array=0-5");
    EXPECT_NE(std::find(script.begin(), script.end(), fmt::format("export METAMER_SPECTRA='{}/spectra'", METAMER_SOURCE_DIR)),
              script.end());
    r = test::runMetamer(fmt::format("batch {} --out {} --slurm --sbatch array=0-9", sweep.string(), out));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("--sbatch: 'array=0-9' is set by the scripts themselves"), std::string::npos) << r.output;
}

// Issue 30 class 8 (issue 31 item 2): two runs of one sweep into one folder at once — a
// resubmitted array while its tasks still run — share the work through the jobs' claims: no job
// fails, none is rendered twice, no temporary is removed from under the other run, and each run
// says which jobs it left to the other.
TEST(BatchCli, TwoRunsIntoOneFolderAtOnceRenderEachJobOnceAndFailNone) {
    const fs::path dir = freshDir("two-runs");
    const fs::path sweep = writeSweep(dir, R"({"write": "png,cube", "size": "96x64"})", 4);
    const std::string out = (dir / "out").string();
    const std::string run = fmt::format("{} batch {} --out {} -q", METAMER_BINARY, sweep.string(), out);
    const test::CliRun r = shell(fmt::format("({0} > {1}/a.log 2>&1; echo $? > {1}/a.code) & "
                                             "({0} > {1}/b.log 2>&1; echo $? > {1}/b.code); wait",
                                             run, dir.string()));
    size_t rendered = 0;
    for (const char* name : {"a", "b"}) {
        const std::vector<std::string> log = lines(dir / fmt::format("{}.log", name));
        std::string text;
        for (const std::string& l : log) text += l + "\n";
        EXPECT_EQ(lines(dir / fmt::format("{}.code", name)), std::vector<std::string>{"0"}) << name << text;
        EXPECT_EQ(text.find("failed:"), std::string::npos) << name << text;
        EXPECT_EQ(text.find("missing"), std::string::npos) << name << text;
        const size_t at = text.find(" rendered, ");
        ASSERT_NE(at, std::string::npos) << text;
        rendered += std::stoul(text.substr(text.rfind(' ', at - 1) + 1));
    }
    EXPECT_EQ(rendered, 8u);  // 4 lights × 2 detectors, each by one of the two runs
    EXPECT_EQ(countFiles(dir / "out", "job.json"), 8u);
    EXPECT_EQ(countFiles(dir / "out", ".tmp-", true), 0u);
    EXPECT_EQ(countFiles(dir / "out", ".claim", true), 0u);
    // Afterwards a third run finds everything done, and clears the index temporary a killed run left.
    std::ofstream(dir / "out" / ".index.csv.tmp-999999-0.csv") << "half an index";
    const test::CliRun again = test::runMetamer(fmt::format("batch {} --out {} -q", sweep.string(), out));
    EXPECT_NE(again.output.find("0 rendered, 8 skipped"), std::string::npos) << again.output;
    EXPECT_FALSE(fs::exists(dir / "out" / ".index.csv.tmp-999999-0.csv"));
    EXPECT_FALSE(fs::exists(dir / "out" / ".claim"));
    (void)r;
}

namespace {

std::string bytesOf(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

// Issue 31, item 1: a job's files do not depend on what its process rendered before. The same job
// of spheres.json (hemisphere lights and glossy spheres: where lavapipe's uniform inlining made a
// pipeline's first frame differ in the last bit, shaders/runtime_value.glsl) rendered as the first
// job of a batch, as a later one, as one shard's, and alone by `metamer render` gives the same
// bytes in its cube, its XYZ and its PNG.
TEST(BatchCli, AJobGivesTheSameBytesFirstLaterAloneOrInAShard) {
    const fs::path dir = freshDir("same-bytes");
    auto sweep = [&](const std::string& name, const std::string& values) {
        std::ofstream(dir / name) << fmt::format(
            R"({{"scenes": ["{}/scenes/spheres.json"], "render": {{"size": "48x32", "write": "cube,xyz,png"}},
                 "axes": [{{"set": "lights.0.scale", "values": [{}]}}]}})",
            METAMER_SOURCE_DIR, values);
        return (dir / name).string();
    };
    const std::string first = sweep("first.json", "1, 2, 3"), later = sweep("later.json", "3, 2, 1");
    for (const auto& [s, out] : {std::pair{first, "a"}, std::pair{later, "b"}}) {
        const test::CliRun r = test::runMetamer(fmt::format("batch {} --out {} -q", s, (dir / out).string()));
        ASSERT_EQ(r.code, 0) << r.output;
    }
    const test::CliRun shard = test::runMetamer(fmt::format("batch {} --out {} --shard 2/3 -q", later, (dir / "c").string()));
    ASSERT_EQ(shard.code, 0) << shard.output;
    const test::CliRun alone = test::runMetamer(fmt::format(
        "render {}/scenes/spheres.json --set lights.0.scale=1 --set camera.width=48 --set camera.height=32 "
        "--write cube,xyz,png -o {}",
        METAMER_SOURCE_DIR, (dir / "alone").string()));
    ASSERT_EQ(alone.code, 0) << alone.output;
    // The job with scale 1: first in a, last in b, the only job of shard 2/3 in c.
    fs::path job;
    for (const auto& e : fs::directory_iterator(dir / "a"))
        if (e.is_directory() && bytesOf(e.path() / "job.json").find("lights.0.scale=1") != std::string::npos) job = e.path();
    ASSERT_FALSE(job.empty());
    for (const char* file : {"spheres.exr", "spheres.xyz.exr", "spheres.png"}) {
        const std::string bytes = bytesOf(job / file);
        ASSERT_FALSE(bytes.empty()) << file;
        EXPECT_TRUE(bytes == bytesOf(dir / "b" / job.filename() / file)) << file << ": first vs later job";
        EXPECT_TRUE(bytes == bytesOf(dir / "c" / job.filename() / file)) << file << ": first vs a shard's";
        EXPECT_TRUE(bytes == bytesOf(dir / "alone" / file)) << file << ": in a batch vs alone";
    }
}

// Issue 31, item 4: after an edit the index says which records are current; given the sweep it
// lists exactly the sweep's jobs, a job without a record as missing; settings a job left alone
// show the value used, axes are columns, and every record carries the Metamer version.
TEST(BatchCli, TheIndexMarksWhatIsCurrentAndListsTheSweepsJobsMissingOrNot) {
    const fs::path dir = freshDir("index");
    const std::string out = (dir / "out").string();
    const fs::path sweep = writeSweep(dir, R"({"size": "8x8", "write": "png"})", 2);  // 2 lights × 2 detectors
    ASSERT_EQ(test::runMetamer(fmt::format("batch {} --out {} -q", sweep.string(), out)).code, 0);
    // The edit: every job gets a new id (a setting changed), the old records stay on disk.
    writeSweep(dir, R"({"size": "8x8", "write": "png", "bits": 16})", 2);
    test::CliRun r = test::runMetamer(fmt::format("batch {} --out {} -q", sweep.string(), out));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("note: 4 records of jobs that are not this sweep's"), std::string::npos) << r.output;
    std::vector<std::string> index = lines(dir / "out" / "index.csv");
    EXPECT_EQ(index.size(), 5u);  // the sweep's 4 jobs, not 8 records
    const std::string header = index[0];
    for (const char* column : {",current,", ",bits,", ",adapt,", ",display,", ",grid,", ",axis:light,",
                               ",axis:detector,", ",metamer_version,", ",spectra_digest,"})
        EXPECT_NE(header.find(column), std::string::npos) << column << " in " << header;
    EXPECT_NE(index[1].find(",done,true,"), std::string::npos) << index[1];
    EXPECT_NE(index[1].find(",bradford,"), std::string::npos) << index[1];  // adaptation: not set, the default used
    // Without the sweep: all 8 records, the 4 older ones not current.
    r = test::runMetamer(fmt::format("batch --index {}", out));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("note: 4 records are superseded by a later one at the same sweep position"),
              std::string::npos)
        << r.output;
    index = lines(dir / "out" / "index.csv");
    EXPECT_EQ(index.size(), 9u);
    EXPECT_EQ(std::count_if(index.begin(), index.end(),
                            [](const std::string& l) { return l.find(",false,") != std::string::npos; }),
              4);
    // A job whose record is gone (a task that died): missing, not absent.
    for (const auto& e : fs::directory_iterator(dir / "out")) {
        const std::string j = bytesOf(e.path() / "job.json");
        if (j.find("\"bits\": 16") != std::string::npos && j.find("\"position\": 3") != std::string::npos) {
            fs::remove_all(e.path());
            break;
        }
    }
    r = test::runMetamer(fmt::format("batch {} --index {}", sweep.string(), out));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("index: 3 job records (3 done, 0 failed), 1 jobs without a record (status missing)"),
              std::string::npos)
        << r.output;
    index = lines(dir / "out" / "index.csv");
    ASSERT_EQ(index.size(), 5u);
    EXPECT_NE(index[4].find(",missing,true,"), std::string::npos) << index[4];
    EXPECT_NE(index[4].find("illuminants/A"), std::string::npos) << index[4];  // what it would render
}

// Issue 35, item 5: a job's record says how many threads rendered it (--threads, as the Slurm
// task passes it).
TEST(BatchCli, TheRecordKeepsTheThreadCount) {
    const fs::path dir = freshDir("threads");
    const fs::path sweep = writeSweep(dir, R"({"write": "png", "size": "24x16"})", 1);
    test::CliRun r = test::runMetamer("batch " + sweep.string() + " --out " + (dir / "out").string() + " --threads 1 -q");
    ASSERT_EQ(r.code, 0) << r.output;
    size_t records = 0;
    for (const auto& e : fs::directory_iterator(dir / "out"))
        if (e.is_directory() && fs::exists(e.path() / "job.json")) {
            std::ifstream in(e.path() / "job.json");
            const nlohmann::json record = nlohmann::json::parse(in);
            EXPECT_EQ(record.value("threads", 0), 1) << e.path();
            ++records;
        }
    EXPECT_EQ(records, 2u);
}

// Issue 49, item 2: a sweep that draws its scenes. Every job's drawn values are in its record and
// the index; the dataset is the same bytes run whole or in shards; and a job re-rendered alone from
// its record's overrides gives the same cube.
TEST(BatchCli, DrawnScenesAreRecordedAndEachJobRendersAloneToTheSameBytes) {
    const fs::path dir = freshDir("draws");
    std::ofstream(dir / "draws.json") << fmt::format(
        R"({{"scenes": ["{}/scenes/spheres.json"],
             "render": {{"size": "32x24", "write": "cube,reflectance,illumination,ids,depth,normal", "format": "exr,hdf5,arad"}},
             "draws": {{"count": 4, "seed": 5, "values": [
               {{"name": "light", "set": "lights.0.spectrum",
                 "choose": ["illuminants/FL11", {{"daylight_cct": [4000, 10000]}}, {{"blackbody_k": [2500, 3500]}}]}},
               {{"name": "paint", "set": "materials.matte.diffuse", "choose_spectra": "reflectances/cie_2017_ces"}},
               {{"name": "level", "set": "lights.0.scale", "uniform": [0.5, 2]}}]}}}})",
        METAMER_SOURCE_DIR);
    const std::string sweep = (dir / "draws.json").string();
    ASSERT_EQ(test::runMetamer(fmt::format("batch {} --out {} -q", sweep, (dir / "whole").string())).code, 0);
    for (const char* shard : {"0/2", "1/2"}) {
        const test::CliRun r = test::runMetamer(fmt::format("batch {} --out {} --shard {} -q", sweep, (dir / "shards").string(), shard));
        ASSERT_EQ(r.code, 0) << r.output;
    }
    size_t jobs = 0;
    for (const auto& e : fs::directory_iterator(dir / "whole")) {
        if (!e.is_directory()) continue;
        ++jobs;
        const nlohmann::json record = nlohmann::json::parse(bytesOf(e.path() / "job.json"));
        const auto& axes = record.at("axes");
        ASSERT_TRUE(axes.contains("draw") && axes.contains("light") && axes.contains("paint") && axes.contains("level"))
            << record.dump();
        // Every file but the record (which holds timings): the cube in each container, the ground truth.
        size_t files = 0;
        for (const auto& f : fs::directory_iterator(e.path())) {
            if (f.path().filename() == "job.json") continue;
            ++files;
            EXPECT_TRUE(bytesOf(f.path()) == bytesOf(dir / "shards" / e.path().filename() / f.path().filename()))
                << e.path().filename() << "/" << f.path().filename() << ": whole vs shards";
        }
        EXPECT_EQ(files, 14u) << e.path();  // 3 containers × (cube, reflectance, illumination), ids + legend, depth, normal, mask
        if (axes.at("draw") != 2) continue;
        // Re-rendered alone with the record's overrides.
        std::string sets;
        for (const auto& o : record.at("settings").at("set")) sets += " --set '" + o.get<std::string>() + "'";
        const test::CliRun alone = test::runMetamer(fmt::format("render {}/scenes/spheres.json{} --set camera.width=32 "
                                                                "--set camera.height=24 --write cube,reflectance,illumination,"
                                                                "ids,depth,normal --format exr,hdf5,arad -o {}",
                                                                METAMER_SOURCE_DIR, sets, (dir / "alone").string()));
        ASSERT_EQ(alone.code, 0) << alone.output;
        for (const char* f : {"spheres.exr", "spheres.h5", "spheres.mat", "spheres.reflectance.mat", "spheres.illumination.h5",
                              "spheres.ids.exr", "spheres.mask.png", "spheres.depth.exr"})
            EXPECT_TRUE(bytesOf(e.path() / f) == bytesOf(dir / "alone" / f)) << f << " in the batch vs alone";
    }
    EXPECT_EQ(jobs, 4u);
    ASSERT_TRUE(fs::exists(dir / "alone" / "spheres.exr"));
    const test::CliRun index = test::runMetamer(fmt::format("batch --index {}", (dir / "whole").string()));
    ASSERT_EQ(index.code, 0) << index.output;
    const std::string csv = bytesOf(dir / "whole" / "index.csv");
    for (const char* column : {"draw", "light", "paint", "level"})
        EXPECT_NE(csv.substr(0, csv.find('\n')).find(column), std::string::npos) << column << " in " << csv.substr(0, csv.find('\n'));
}
