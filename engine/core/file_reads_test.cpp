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
