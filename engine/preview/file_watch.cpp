#include "preview/file_watch.h"

namespace metamer::preview {

FileWatch::FileWatch(std::filesystem::path path, double interval_s)
    : path_(std::move(path)), interval_(interval_s), last_(std::chrono::steady_clock::now()), seen_(stamp()) {}

FileWatch::Stamp FileWatch::stamp() const {
    Stamp s;
    std::error_code ec;
    s.time = std::filesystem::last_write_time(path_, ec);
    if (ec) return Stamp{};
    s.size = std::filesystem::file_size(path_, ec);
    s.exists = !ec;
    return s;
}

bool FileWatch::changed() {
    auto now = std::chrono::steady_clock::now();
    if (now - last_ < interval_) return false;
    last_ = now;
    Stamp s = stamp();
    // A file being replaced may be missing for a moment: wait for it to come back.
    if (!s.exists || s == seen_) return false;
    seen_ = s;
    return true;
}

}  // namespace metamer::preview
