// The input files a piece of work reads, so that what it produced can be keyed on their content
// (metamer batch's job ids: editing a spectrum changes the id of every job that reads it). Each
// reader of user data calls noteFileRead() when it opens a file; a FileReadLog alive on the same
// thread collects the paths (nested logs each see every read). Without a log it costs nothing.
// Tests: engine/core/file_reads_test.cpp.
#pragma once

#include <filesystem>
#include <vector>

namespace metamer {

void noteFileRead(const std::filesystem::path& path);

class FileReadLog {
public:
    FileReadLog();
    ~FileReadLog();
    FileReadLog(const FileReadLog&) = delete;
    FileReadLog& operator=(const FileReadLog&) = delete;

    // Every file noted while this log was alive: absolute, lexically normal, sorted, each once.
    std::vector<std::filesystem::path> files() const;

private:
    friend void noteFileRead(const std::filesystem::path& path);
    FileReadLog* outer_;
    std::vector<std::filesystem::path> files_;
};

}  // namespace metamer
