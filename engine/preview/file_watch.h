// Notices when a file changes on disk (the preview reloads its scene): its modification time and
// size, polled at most every `interval_s` seconds. Editors that replace the file (write a new
// one and rename it) are seen too, since the new file has a new time.
// Tests: engine/preview/preview_settings_test.cpp.
#pragma once

#include <chrono>
#include <filesystem>

namespace metamer::preview {

class FileWatch {
public:
    explicit FileWatch(std::filesystem::path path, double interval_s = 0.5);
    // True once per change since the last call that returned true (or since construction).
    bool changed();

private:
    struct Stamp {
        std::filesystem::file_time_type time{};
        std::uintmax_t size = 0;
        bool exists = false;
        bool operator==(const Stamp& o) const { return time == o.time && size == o.size && exists == o.exists; }
    };
    Stamp stamp() const;

    std::filesystem::path path_;
    std::chrono::duration<double> interval_;
    std::chrono::steady_clock::time_point last_;
    Stamp seen_;
};

}  // namespace metamer::preview
