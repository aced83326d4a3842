#include "core/file_reads.h"

#include <gtest/gtest.h>

#include <thread>

using namespace metamer;
namespace fs = std::filesystem;

TEST(FileReadLog, CollectsEachFileOnceSortedAndAbsoluteInNestedLogsOnly) {
    noteFileRead("before.csv");  // no log: nothing happens
    FileReadLog outer;
    noteFileRead("b/x.csv");
    {
        FileReadLog inner;
        noteFileRead("a/./y.csv");
        noteFileRead("b/x.csv");
        EXPECT_EQ(inner.files(), (std::vector<fs::path>{fs::absolute("a/y.csv"), fs::absolute("b/x.csv")}));
    }
    std::thread([] { noteFileRead("other-thread.csv"); }).join();  // another thread's reads are its own
    EXPECT_EQ(outer.files(), (std::vector<fs::path>{fs::absolute("a/y.csv"), fs::absolute("b/x.csv")}));
}

// A stream without a size (standard input) is read whole up to the cap, then refused naming what
// it was, before reading much past it.
TEST(FileReads, AStreamIsReadWholeUpToItsCap) {
    std::FILE* f = std::tmpfile();
    ASSERT_NE(f, nullptr);
    const std::string text(3 << 20, 'x');  // three of its 1 MiB blocks
    std::fwrite(text.data(), 1, text.size(), f);
    std::rewind(f);
    EXPECT_EQ(readWholeStream(f, Where{"<stdin>"}, "scene read from standard input"), text);
    std::rewind(f);
    try {
        readWholeStream(f, Where{"<stdin>"}, "scene read from standard input", 2 << 20);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(e.text().find("<stdin>"), std::string::npos) << e.text();
        EXPECT_NE(e.text().find("scene read from standard input is over 2 MiB"), std::string::npos) << e.text();
    }
    std::fclose(f);
}
