// SIGINT and SIGTERM during `metamer render`, for real: a render big enough to be caught in the
// middle is started, signalled, and the output folder inspected. An interrupted run must exit
// with 128 + the signal, leave no temporary file, and leave the files of an earlier run
// byte-identical (engine/app/main.cpp's handler, engine/io/atomic_file.h).
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

const std::string kScene = std::string(METAMER_SOURCE_DIR) + "/tests/data/cli/small.json";

fs::path freshDir(const std::string& name) {
    fs::path d = fs::temp_directory_path() / ("metamer-interrupt-" + std::to_string(::getpid())) / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

// Starts `metamer ARGS...`, its output going to DIR/../NAME.log.
pid_t startMetamer(const fs::path& out, const std::vector<std::string>& args) {
    std::vector<std::string> argv = {METAMER_BINARY};
    argv.insert(argv.end(), args.begin(), args.end());
    std::string log = (out.parent_path() / (out.filename().string() + ".log")).string();
    pid_t pid = fork();
    if (pid == 0) {
        int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
        }
        std::vector<char*> cargv;
        for (auto& a : argv) cargv.push_back(a.data());
        cargv.push_back(nullptr);
        execv(cargv[0], cargv.data());
        _exit(127);
    }
    return pid;
}

// Starts `metamer render SCENE --out DIR ARGS...`.
pid_t start(const fs::path& out, const std::vector<std::string>& args) {
    std::vector<std::string> argv = {"render", kScene, "--out", out.string()};
    argv.insert(argv.end(), args.begin(), args.end());
    return startMetamer(out, argv);
}

// Exit status as a shell reports it: the code, or 128 + the signal that killed it.
int wait(pid_t pid) {
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string readFile(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

// Every file in the folder and its bytes.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& e : fs::directory_iterator(dir)) files[e.path().filename().string()] = readFile(e.path());
    return files;
}

bool hasTemporary(const fs::path& dir) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().filename().string().find(".tmp-") != std::string::npos) return true;
    return false;
}

std::string log(const fs::path& out) { return readFile(out.parent_path() / (out.filename().string() + ".log")); }

// A first, small render into `out`: the files an interrupted run must not harm.
std::map<std::string, std::string> previousRun(const fs::path& out) {
    pid_t pid = start(out, {"--backend", "cpu"});
    EXPECT_EQ(wait(pid), 0) << log(out);
    auto files = snapshot(out);
    EXPECT_EQ(files.size(), 2u);  // small.exr, small.png
    return files;
}

// The same scene at 512 × 512 (a 93 MB cube), for the tests that signal when the write starts;
// and at 1024 × 1024 (373 MB, seconds to render and write on any machine), for those that signal
// after a fixed half second: it must still be running then.
const std::vector<std::string> kBig = {"--set", "camera.width=512", "--set", "camera.height=512"};
const std::vector<std::string> kBigger = {"--set", "camera.width=1024", "--set", "camera.height=1024"};

std::vector<std::string> plus(std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

}  // namespace

TEST(InterruptedRun, SigintDuringTheRenderLeavesThePreviousFilesAndNoTemporary) {
    fs::path out = freshDir("sigint");
    auto before = previousRun(out);
    pid_t pid = start(out, plus(kBigger, {"--backend", "cpu"}));
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    ASSERT_EQ(::kill(pid, SIGINT), 0);
    EXPECT_EQ(wait(pid), 128 + SIGINT) << log(out);
    EXPECT_FALSE(hasTemporary(out));
    EXPECT_TRUE(snapshot(out) == before) << "the previous files changed";
}

TEST(InterruptedRun, SigtermWhileTheCubeIsBeingWrittenRemovesTheTemporary) {
    // Wait until the temporary cube appears, so the signal lands in the middle of the write.
    fs::path out = freshDir("sigterm-write");
    auto before = previousRun(out);
    pid_t pid = start(out, plus(kBig, {"--backend", "cpu"}));
    bool sawTemporary = false;
    for (auto t0 = Clock::now(); Clock::now() - t0 < std::chrono::seconds(60);) {
        if ((sawTemporary = hasTemporary(out))) break;
        if (waitpid(pid, nullptr, WNOHANG) != 0) break;  // finished (or died) without our seeing it
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_TRUE(sawTemporary) << "the render never wrote a temporary file\n" << log(out);
    ASSERT_EQ(::kill(pid, SIGTERM), 0);
    EXPECT_EQ(wait(pid), 128 + SIGTERM) << log(out);
    EXPECT_FALSE(hasTemporary(out));
    EXPECT_TRUE(snapshot(out) == before) << "the previous files changed";
    // One line says why it ended (a Slurm task's log shows it).
    EXPECT_NE(log(out).find("metamer: stopped by SIGTERM (a time limit, scancel or kill)"), std::string::npos) << log(out);
}

TEST(InterruptedRun, SigintWhileStripsStreamToTheFilesRemovesEveryTemporary) {
    // Over the memory budget the GPU path streams every output strip by strip: the temporary
    // files exist for the whole render, and all of them must go.
    fs::path out = freshDir("sigint-strips");
    auto before = previousRun(out);
    pid_t pid = start(out, plus(kBig, {"--memory-budget", "16", "--write", "cube,png,xyz"}));
    bool sawTemporary = false;
    for (auto t0 = Clock::now(); Clock::now() - t0 < std::chrono::seconds(60);) {
        if ((sawTemporary = hasTemporary(out))) break;
        if (waitpid(pid, nullptr, WNOHANG) != 0) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_TRUE(sawTemporary) << log(out);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // a few strips in
    ASSERT_EQ(::kill(pid, SIGINT), 0);
    EXPECT_EQ(wait(pid), 128 + SIGINT) << log(out);
    EXPECT_FALSE(hasTemporary(out));
    EXPECT_TRUE(snapshot(out) == before) << "the previous files changed";
}

TEST(InterruptedRun, AnInterruptedFirstRunLeavesAnEmptyFolder) {
    fs::path out = freshDir("first") / "out";
    pid_t pid = start(out, plus(kBigger, {"--backend", "cpu"}));
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    ASSERT_EQ(::kill(pid, SIGTERM), 0);
    EXPECT_EQ(wait(pid), 128 + SIGTERM) << log(out);
    std::error_code ec;
    EXPECT_TRUE(!fs::exists(out) || fs::is_empty(out, ec));
}

// Issue 51, class 4: a capture of thousands of frames stages them in one hidden folder; a signal
// in the middle removes the folder and all it holds, and the previous capture is untouched.
TEST(InterruptedRun, SigintDuringALongCaptureRemovesItsStagingFolder) {
    fs::path out = freshDir("sigint-capture");
    pid_t pid = start(out, {"--backend", "cpu", "--sensor", "aps_c_rggb"});
    ASSERT_EQ(wait(pid), 0) << log(out);
    const auto before = snapshot(out);
    ASSERT_EQ(before.size(), 7u);  // cube, PNG, raw PNG, DNG, JSON, developed sRGB PNG, electrons
    pid = startMetamer(out, {"capture", (out / "small.exr").string(), "--sensor", "aps_c_rggb", "--frames", "100000",
                             "--out", out.string()});
    bool sawStaging = false;
    for (auto t0 = Clock::now(); Clock::now() - t0 < std::chrono::seconds(60);) {
        std::error_code ec;
        for (const auto& e : fs::directory_iterator(out, ec))
            if (e.path().filename().string().find(".staging-") != std::string::npos) sawStaging = true;
        if (sawStaging || waitpid(pid, nullptr, WNOHANG) != 0) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_TRUE(sawStaging) << log(out);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // some hundreds of frames in
    ASSERT_EQ(::kill(pid, SIGINT), 0);
    EXPECT_EQ(wait(pid), 128 + SIGINT) << log(out);
    EXPECT_TRUE(snapshot(out) == before) << "the folder changed";
}
