// The pipeline cache on disk (vk/pipeline_cache): written for this device and driver when a
// context goes, read by the next; a file that is not this driver's is ignored and replaced, and
// rendering is unaffected either way (validation on).
#include "vk/pipeline_cache.h"

#include "render/render_job.h"
#include "vk/context.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <fstream>
#include <unistd.h>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
    fs::path dir = fs::temp_directory_path() / fmt::format("metamer-pcache-{}-{}", ::getpid(), name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

// A small render through the whole GPU path with the cache in `folder`.
void renderWith(const fs::path& folder, const fs::path& out) {
    ::setenv("METAMER_PIPELINE_CACHE", folder.c_str(), 1);
    RenderJob job;
    job.scene = fs::path(METAMER_SOURCE_DIR) / "scenes" / "spheres.json";
    job.overrides = {"camera.width=16", "camera.height=16"};
    job.outDir = out;
    job.validation = true;
    const RenderJobResult r = runRenderJob(job);
    EXPECT_EQ(r.validationErrors, 0u);
}

std::vector<fs::path> files(const fs::path& dir) {
    std::vector<fs::path> f;
    for (const auto& e : fs::directory_iterator(dir)) f.push_back(e.path());
    return f;
}

}  // namespace

TEST(PipelineCache, WrittenForThisDeviceReadBackAndStaleFilesReplaced) {
    const fs::path dir = scratch("cache"), out = scratch("out");
    renderWith(dir, out);
    std::vector<fs::path> written = files(dir);
    ASSERT_EQ(written.size(), 1u);  // one file, no temporary left
    const std::string name = written[0].filename().string();
    EXPECT_EQ(name.rfind("pipelines-", 0), 0u) << name;
    const auto size = fs::file_size(written[0]);
    EXPECT_GE(size, 32u);  // at least Vulkan's header

    // The next context reads it.
    {
        vk::ContextOptions o;
        o.pipelineCacheFolder = dir;
        vk::Context ctx(o);
        EXPECT_EQ(ctx.pipelineCacheFile().file(), written[0]);
        EXPECT_EQ(ctx.pipelineCacheFile().loadedBytes(), size);
        EXPECT_EQ(ctx.pipelineCacheFile().ignoredBecause(), "");
    }
    // Garbage, or a header from another device, is ignored, the render is unaffected, and the file
    // is replaced by this driver's.
    for (const std::string& junk : {std::string("not a cache"), std::string(64, '\x01')}) {
        std::ofstream(written[0], std::ios::binary | std::ios::trunc) << junk;
        {
            vk::ContextOptions o;
            o.pipelineCacheFolder = dir;
            vk::Context ctx(o);
            EXPECT_EQ(ctx.pipelineCacheFile().loadedBytes(), 0u);
            EXPECT_NE(ctx.pipelineCacheFile().ignoredBecause(), "");
        }
        renderWith(dir, out);
        EXPECT_EQ(fs::file_size(written[0]), size);
        EXPECT_EQ(files(dir).size(), 1u);
    }
    // A FIFO where the file goes is not opened (it would block every render until a writer came):
    // ignored as such, the render unaffected; saving replaces it with the cache.
    fs::remove(written[0]);
    ASSERT_EQ(::mkfifo(written[0].c_str(), 0600), 0);
    {
        vk::ContextOptions o;
        o.pipelineCacheFolder = dir;
        vk::Context ctx(o);
        EXPECT_EQ(ctx.pipelineCacheFile().loadedBytes(), 0u);
        EXPECT_NE(ctx.pipelineCacheFile().ignoredBecause().find("a FIFO, not a regular file"), std::string::npos)
            << ctx.pipelineCacheFile().ignoredBecause();
    }
    renderWith(dir, out);
    EXPECT_TRUE(fs::is_regular_file(written[0]));
    // "off": nothing on disk.
    const fs::path none = scratch("off");
    ::setenv("METAMER_PIPELINE_CACHE", "off", 1);
    EXPECT_TRUE(vk::pipelineCacheFolder().empty());
    {
        vk::Context ctx(vk::contextOptionsFromEnvironment());
        EXPECT_TRUE(ctx.pipelineCacheFile().file().empty());
    }
    ::unsetenv("METAMER_PIPELINE_CACHE");
}
