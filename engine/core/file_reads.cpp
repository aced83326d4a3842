#include "core/file_reads.h"

#include <algorithm>

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

}  // namespace metamer
