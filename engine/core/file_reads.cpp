#include "core/file_reads.h"

#include <algorithm>
#include <fstream>
#include <sstream>

namespace metamer {

namespace {
thread_local FileReadLog* gInnermost = nullptr;
}

FileReadLog::FileReadLog() : outer_(gInnermost) { gInnermost = this; }

FileReadLog::~FileReadLog() { gInnermost = outer_; }

void noteFileRead(const std::filesystem::path& path) {
    if (!gInnermost) return;
    std::error_code ec;
    std::filesystem::path p = std::filesystem::absolute(path, ec);
    if (ec) p = path;
    p = p.lexically_normal();
    for (FileReadLog* log = gInnermost; log; log = log->outer_) log->files_.push_back(p);
}

std::vector<std::filesystem::path> FileReadLog::files() const {
    std::vector<std::filesystem::path> f = files_;
    std::sort(f.begin(), f.end());
    f.erase(std::unique(f.begin(), f.end()), f.end());
    return f;
}

namespace {

std::string named(const std::filesystem::path& path, const Where& where, std::string_view what) {
    const std::string role = what.empty() ? std::string("file") : std::string(what);
    return where.file == path.string() ? role : fmt::format("{} '{}'", role, path.string());
}

}  // namespace

void requireRegularFile(const std::filesystem::path& path, const Where& where, std::string_view what) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (!fs::exists(st)) {
        // A dangling link or a folder that cannot be searched: "not found" either way, with why.
        if (ec && ec != std::errc::no_such_file_or_directory)
            failInput(where, "{} cannot be looked at: {}", named(path, where, what), ec.message());
        throw NotFoundError(where, fmt::format("{} not found", named(path, where, what)));
    }
    if (fs::is_regular_file(st)) return;
    if (fs::is_directory(st)) failInput(where, "{} is a folder, not a file", named(path, where, what));
    failInput(where, "{} is not a regular file ({})", named(path, where, what), specialFileKind(st));
}

const char* specialFileKind(const std::filesystem::file_status& st) {
    namespace fs = std::filesystem;
    if (!fs::exists(st) || fs::is_regular_file(st)) return nullptr;
    return fs::is_directory(st)        ? "a folder"
           : fs::is_fifo(st)           ? "a FIFO"
           : fs::is_character_file(st) ? "a character device"
           : fs::is_block_file(st)     ? "a block device"
           : fs::is_socket(st)         ? "a socket"
           : fs::is_symlink(st)        ? "a symbolic link"
                                       : "not a plain file";
}

std::string readWholeFile(const std::filesystem::path& path, const Where& where, std::string_view what,
                          std::uintmax_t maxBytes) {
    requireRegularFile(path, where, what);
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (!ec && size > maxBytes)
        failInput(where, "{} is {} bytes; at most {} MiB is read", named(path, where, what), size, maxBytes >> 20);
    noteFileRead(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) failInput(where, "cannot open the {}", named(path, where, what));
    std::ostringstream ss;
    ss << in.rdbuf();
    std::string bytes = ss.str();
    // A file that grew while it was read (a log being written) is held to the same limit.
    if (bytes.size() > maxBytes)
        failInput(where, "{} is over {} MiB", named(path, where, what), maxBytes >> 20);
    return bytes;
}

std::string readWholeStream(std::FILE* stream, const Where& where, std::string_view what, std::uintmax_t maxBytes) {
    std::string bytes;
    std::vector<char> block(1 << 20);
    for (;;) {
        const size_t got = std::fread(block.data(), 1, block.size(), stream);
        bytes.append(block.data(), got);
        if (bytes.size() > maxBytes) failInput(where, "the {} is over {} MiB", what, maxBytes >> 20);
        if (got < block.size()) {
            if (std::ferror(stream)) failInput(where, "the {} could not be read", what);
            return bytes;
        }
    }
}

}  // namespace metamer
