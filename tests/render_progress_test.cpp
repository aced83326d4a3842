// The render job's progress hook (render/render_progress.h): the order of its calls, and a hook
// that throws stops the render leaving no output file — what the Python binding's Ctrl-C and
// callbacks rely on.
#include "render/render_job.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace metamer;

namespace {

RenderJob smallJob(const std::string& name) {
    RenderJob job;
    job.scene = fs::path(METAMER_SOURCE_DIR) / "tests" / "data" / "cli" / "small.json";
    job.outDir = fs::temp_directory_path() / ("metamer-render-progress-" + name);
    fs::remove_all(job.outDir);
    job.validation = true;
    return job;
}

struct Stop : std::runtime_error {
    Stop() : std::runtime_error("stopped by the hook") {}
};

}  // namespace

TEST(RenderProgress, StripsAreCountedFromZeroToTheTotal) {
    RenderJob job = smallJob("strips");
    job.memoryBudget = 96 << 10;  // a few rows per strip
    std::vector<RenderProgress> seen;
    job.progress = [&](const RenderProgress& p) { seen.push_back(p); };
    const RenderJobResult r = runRenderJob(job);
    EXPECT_EQ(r.validationErrors, 0u);
    ASSERT_GE(seen.size(), 3u);
    EXPECT_EQ(seen.front().done, 0);
    EXPECT_EQ(seen.back().done, seen.back().total);
    for (size_t i = 0; i < seen.size(); ++i) {
        EXPECT_STREQ(seen[i].unit, "strip");
        EXPECT_EQ(seen[i].done, int(i));
        EXPECT_EQ(seen[i].total, seen.front().total);
        if (i) EXPECT_GE(seen[i].seconds, seen[i - 1].seconds);
    }
    EXPECT_GT(r.threads, 0);
}

TEST(RenderProgress, WholeFramesArePassByPassAndTheSameImage) {
    RenderJob job = smallJob("passes");
    job.frames = 3;
    job.write = {"cube"};
    std::vector<int> done;
    job.progress = [&](const RenderProgress& p) {
        EXPECT_STREQ(p.unit, "pass");
        EXPECT_EQ(p.total % 3, 0);  // the frame's passes, three times
        done.push_back(p.done);
    };
    const RenderJobResult r = runRenderJob(job);
    EXPECT_EQ(r.validationErrors, 0u);
    ASSERT_GE(done.size(), 2u);
    for (size_t i = 0; i < done.size(); ++i) EXPECT_EQ(done[i], int(i));
    // Submitted pass by pass, the cube is the one a single submission draws.
    RenderJob whole = smallJob("passes-whole");
    whole.write = {"cube"};
    runRenderJob(whole);
    auto bytes = [](const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    EXPECT_EQ(bytes(job.outDir / "small.exr"), bytes(whole.outDir / "small.exr"));

    RenderJob display = smallJob("display-frames");  // no bands: the response pass, frame by frame
    display.write = {"png"};
    display.frames = 2;
    std::vector<int> frames;
    display.progress = [&](const RenderProgress& p) {
        EXPECT_STREQ(p.unit, "frame");
        frames.push_back(p.done);
    };
    runRenderJob(display);
    EXPECT_EQ(frames, (std::vector<int>{0, 1, 2}));
}

TEST(RenderProgress, AHookThatThrowsStopsTheRenderAndLeavesNoFile) {
    RenderJob job = smallJob("stop");
    job.memoryBudget = 96 << 10;
    int calls = 0;
    job.progress = [&](const RenderProgress& p) {
        ++calls;
        if (p.done == 2) throw Stop();
    };
    EXPECT_THROW(runRenderJob(job), Stop);
    EXPECT_EQ(calls, 3);
    // The folder may have been made for the outputs; nothing is in it, not even a temporary file.
    if (fs::exists(job.outDir)) EXPECT_TRUE(fs::is_empty(job.outDir));
}

TEST(RenderProgress, TheCpuReferenceCountsRowsAndCanBeStopped) {
    RenderJob job = smallJob("rows");
    job.backend = Backend::Cpu;
    job.validation = false;
    std::vector<int> done;
    job.progress = [&](const RenderProgress& p) {
        EXPECT_STREQ(p.unit, "row");
        EXPECT_EQ(p.total, 32);
        done.push_back(p.done);
    };
    runRenderJob(job);
    ASSERT_GE(done.size(), 2u);
    EXPECT_EQ(done.front(), 0);
    EXPECT_EQ(done.back(), 32);
    EXPECT_TRUE(std::is_sorted(done.begin(), done.end()));

    RenderJob stopped = smallJob("rows-stop");
    stopped.backend = Backend::Cpu;
    stopped.validation = false;
    stopped.overrides = {"camera.width=160", "camera.height=120"};  // long enough for a report between rows
    // The first report after 0: between rows when the render is slow enough, else the last one,
    // which still comes before any file is written.
    stopped.progress = [](const RenderProgress& p) {
        if (p.done > 0) throw Stop();
    };
    EXPECT_THROW(runRenderJob(stopped), Stop);
    if (fs::exists(stopped.outDir)) EXPECT_TRUE(fs::is_empty(stopped.outDir));
}
