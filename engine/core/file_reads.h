// The input files a piece of work reads, so that what it produced can be keyed on their content
// (metamer batch's job ids: editing a spectrum changes the id of every job that reads it). Each
// reader of user data calls noteFileRead() when it opens a file; a FileReadLog alive on the same
// thread collects the paths (nested logs each see every read). Without a log it costs nothing.
//
// Every reader of a user's file first calls requireRegularFile (or readWholeFile, which also caps
// the size): the one check that a path names a regular file, so a FIFO cannot block a run, a
// device (/dev/zero) cannot feed it forever and a folder is named as such, not "not found".
// Tests: engine/core/file_reads_test.cpp.
#pragma once

#include "core/error.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace metamer {

// The most Metamer reads whole into memory from a text file (a scene, a CSV table, a sweep or
// tolerance file): 256 MiB. Images and cubes are read by their own libraries, sized from their
// headers.
constexpr std::uintmax_t kMaxTextFileBytes = std::uintmax_t(256) << 20;

// That `path` exists and is a regular file (symbolic links followed). `what` names the file's role
// for the message ("spectrum file"): "spectrum file 'x.csv' not found", "... is a folder, not a
// file", "... is not a regular file (a FIFO)"; the path is left out when `where` already names it.
// Input errors at `where`.
void requireRegularFile(const std::filesystem::path& path, const Where& where, std::string_view what);

// What a file that is not a regular file is, for messages: "a folder", "a FIFO", "a character
// device", "a block device", "a socket", "not a plain file"; null for a regular file or none.
const char* specialFileKind(const std::filesystem::file_status& status);

// requireRegularFile, then that it holds at most `maxBytes` (checked before reading), then its
// bytes; notes the read (noteFileRead).
std::string readWholeFile(const std::filesystem::path& path, const Where& where, std::string_view what,
                          std::uintmax_t maxBytes = kMaxTextFileBytes);

// All of `stream` (standard input: a pipe, a terminal, /dev/zero), which has no size to check
// first: read in blocks, and an input error at `where` naming `what` once it passes `maxBytes`.
std::string readWholeStream(std::FILE* stream, const Where& where, std::string_view what,
                            std::uintmax_t maxBytes = kMaxTextFileBytes);

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
