// AtomicOutput and commitTogether: targets that cannot work are refused when the output is made
// (before any work), and a set of outputs replaces the previous set all or none (issue 19, class 2).
#include "io/atomic_file.h"

#include "core/error.h"
#include "support/temp_folder.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <functional>

using namespace metamer;
using metamer::test::slurp;
using metamer::test::writeText;
namespace fs = std::filesystem;

namespace {

class AtomicFile : public test::TempFolderTest {};

std::string failureOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.text();
    }
    return "";
}

}  // namespace

TEST_F(AtomicFile, TheTemporaryFileExistsFromTheStartAndGoesUnlessCommitted) {
    fs::path temp;
    {
        AtomicOutput out(dir / "a.png");
        temp = out.tempPath();
        EXPECT_TRUE(fs::is_regular_file(temp));  // made by the constructor: the folder is writable
        EXPECT_FALSE(fs::exists(dir / "a.png"));
    }
    EXPECT_FALSE(fs::exists(temp));
    EXPECT_TRUE(namesIn().empty());
}

TEST_F(AtomicFile, TargetsThatCannotWorkAreRefusedWhenMade) {
    fs::create_directories(dir / "taken.png");
    std::string e = failureOf([&] { AtomicOutput out(dir / "taken.png"); });
    EXPECT_NE(e.find("it is a folder; an output replaces a file"), std::string::npos) << e;

    ASSERT_EQ(::mkfifo((dir / "fifo.exr").c_str(), 0600), 0);
    e = failureOf([&] { AtomicOutput out(dir / "fifo.exr"); });
    EXPECT_NE(e.find("it is a FIFO"), std::string::npos) << e;

    writeText(dir / "file", "x");
    e = failureOf([&] { AtomicOutput out(dir / "file" / "a.exr"); });
    EXPECT_NE(e.find("'" + (dir / "file").string() + "' is not a folder (a file)"), std::string::npos) << e;

    e = failureOf([&] { AtomicOutput out("/dev/full/a.exr"); });
    EXPECT_NE(e.find("'/dev/full' is not a folder (a character device)"), std::string::npos) << e;

    // A pseudo file system: nothing can be created in /proc.
    e = failureOf([&] { AtomicOutput out("/proc/a.exr"); });
    EXPECT_NE(e.find("cannot write '/proc/a.exr': cannot create a file in '/proc'"), std::string::npos) << e;
    EXPECT_EQ(liveTempFileCount(), 0);
}

TEST_F(AtomicFile, ALinkAtTheTargetIsReplacedNotFollowed) {
    writeText(dir / "elsewhere", "keep me");
    fs::create_symlink(dir / "elsewhere", dir / "a.txt");
    AtomicOutput out(dir / "a.txt");
    writeText(out.tempPath(), "new");
    out.commit();
    EXPECT_FALSE(fs::is_symlink(dir / "a.txt"));
    EXPECT_EQ(slurp(dir / "a.txt"), "new");
    EXPECT_EQ(slurp(dir / "elsewhere"), "keep me");
}

TEST_F(AtomicFile, ASetReplacesThePreviousSetTogether) {
    writeText(dir / "a.exr", "old a");
    writeText(dir / "b.png", "old b");
    {
        AtomicOutput a(dir / "a.exr"), b(dir / "b.png"), c(dir / "c.h5");
        writeText(a.tempPath(), "new a");
        writeText(b.tempPath(), "new b");
        writeText(c.tempPath(), "new c");
        commitTogether({&a, &b, nullptr, &c});
        EXPECT_TRUE(a.committed() && b.committed() && c.committed());
        commitTogether({&a, &b, &c});  // already committed: nothing to do
    }
    EXPECT_EQ(slurp(dir / "a.exr"), "new a");
    EXPECT_EQ(slurp(dir / "b.png"), "new b");
    EXPECT_EQ(slurp(dir / "c.h5"), "new c");
    EXPECT_EQ(namesIn(), (std::vector<std::string>{"a.exr", "b.png", "c.h5"}));  // nothing kept behind
}

TEST_F(AtomicFile, AFailedRenameLeavesThePreviousSetByteIdentical) {
    writeText(dir / "a.exr", "old a");
    writeText(dir / "b.png", "old b");
    {
        AtomicOutput a(dir / "a.exr"), n(dir / "new.xyz.exr"), b(dir / "b.png"), c(dir / "c.png");
        for (AtomicOutput* o : {&a, &n, &b, &c}) writeText(o->tempPath(), "new");
        // c's target becomes a folder after it was checked: its rename fails after a, n and b went.
        fs::create_directories(dir / "c.png" / "inside");
        const std::string e = failureOf([&] { commitTogether({&a, &n, &b, &c}); });
        EXPECT_NE(e.find("cannot write '" + (dir / "c.png").string() + "'"), std::string::npos) << e;
        EXPECT_NE(e.find("the other files of this run were not put in place"), std::string::npos) << e;
        EXPECT_FALSE(a.committed());
    }
    EXPECT_EQ(slurp(dir / "a.exr"), "old a");
    EXPECT_EQ(slurp(dir / "b.png"), "old b");
    EXPECT_FALSE(fs::exists(dir / "new.xyz.exr"));  // had no previous file: removed again
    EXPECT_EQ(namesIn(), (std::vector<std::string>{"a.exr", "b.png", "c.png"}));  // no temporary, no kept copy
    EXPECT_EQ(liveTempFileCount(), 0);
}

TEST_F(AtomicFile, AMissingTemporaryFileRenamesNothing) {
    writeText(dir / "a.exr", "old a");
    AtomicOutput a(dir / "a.exr"), b(dir / "b.exr");
    writeText(a.tempPath(), "new a");
    fs::remove(b.tempPath());
    const std::string e = failureOf([&] { commitTogether({&a, &b}); });
    EXPECT_NE(e.find("temporary file"), std::string::npos) << e;
    EXPECT_EQ(slurp(dir / "a.exr"), "old a");
    EXPECT_FALSE(fs::exists(dir / "b.exr"));
}

// Issue 51, class 4: a capture's many files are staged whole in one hidden folder and put in place
// with the render's, all or none.
TEST_F(AtomicFile, StagedFilesReplaceThePreviousSetWithTheOutputsTogether) {
    writeText(dir / "a.exr", "old a");
    writeText(dir / "a.raw.png", "old raw");
    {
        AtomicOutput a(dir / "a.exr");
        writeText(a.tempPath(), "new a");
        StagingFolder staging(dir, "capture");
        EXPECT_TRUE(staging.folder().empty());  // nothing made before the first file
        writeFileAtomically(staging.stage("a.raw.png"), "new raw");
        for (int f = 0; f < 200; ++f) writeText(staging.stage(fmt::format("a.raw.{}.json", f)), "frame");
        EXPECT_TRUE(isStagingFolderName(staging.folder().filename().string()));
        EXPECT_FALSE(fs::exists(dir / "a.raw.0.json"));
        commitTogether({&a}, {&staging});
        EXPECT_FALSE(fs::exists(staging.folder()));  // emptied by the renames, the previous files dropped
    }
    EXPECT_EQ(slurp(dir / "a.exr"), "new a");
    EXPECT_EQ(slurp(dir / "a.raw.png"), "new raw");
    EXPECT_EQ(slurp(dir / "a.raw.199.json"), "frame");
    EXPECT_EQ(namesIn().size(), 202u);
    EXPECT_EQ(liveTempFileCount(), 0);
}

TEST_F(AtomicFile, AFailedStagedSetLeavesThePreviousSetAndNoStagingFolder) {
    writeText(dir / "a.exr", "old a");
    writeText(dir / "a.raw.png", "old raw");
    {
        AtomicOutput a(dir / "a.exr");
        writeText(a.tempPath(), "new a");
        StagingFolder staging(dir, "capture");
        writeText(staging.stage("a.raw.png"), "new raw");
        writeText(staging.stage("a.raw.json"), "new json");
        // A folder appears where the last file goes, after it was staged: the renames go back.
        fs::create_directories(dir / "a.raw.json" / "inside");
        const std::string e = failureOf([&] { commitTogether({&a}, {&staging}); });
        EXPECT_NE(e.find("cannot write '" + (dir / "a.raw.json").string() + "'"), std::string::npos) << e;
    }
    EXPECT_EQ(slurp(dir / "a.exr"), "old a");
    EXPECT_EQ(slurp(dir / "a.raw.png"), "old raw");
    EXPECT_EQ(namesIn(), (std::vector<std::string>{"a.exr", "a.raw.json", "a.raw.png"}));
    EXPECT_EQ(liveTempFileCount(), 0);
}

TEST_F(AtomicFile, AStagedTargetThatCannotWorkIsRefusedWhenStaged) {
    ASSERT_EQ(::mkfifo((dir / "a.raw.1.png").c_str(), 0600), 0);  // a rename would replace it unawares
    StagingFolder staging(dir, "capture");
    writeText(staging.stage("a.raw.0.png"), "frame 0");
    std::string e = failureOf([&] { staging.stage("a.raw.1.png"); });
    EXPECT_NE(e.find("it is a FIFO; an output replaces a file"), std::string::npos) << e;
    e = failureOf([&] { staging.stage("a.raw.0.png"); });
    EXPECT_NE(e.find("cannot write '" + (dir / "a.raw.0.png").string() + "' twice"), std::string::npos) << e;
}

TEST_F(AtomicFile, ASignalEmptiesAndRemovesAStagingFolderHoweverManyFilesItHolds) {
    StagingFolder staging(dir, "capture");
    for (int f = 0; f < 500; ++f) writeText(staging.stage(fmt::format("frame.{}.png", f)), "x");
    AtomicOutput inside(staging.stage("frame.json"));  // a temporary being written in it
    EXPECT_EQ(liveTempFileCount(), 2);                 // the folder and the temporary: two entries
    removeLiveTempFiles();                             // what the SIGINT/SIGTERM handler calls
    EXPECT_TRUE(namesIn().empty());
}
