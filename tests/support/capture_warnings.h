// Warnings (core/error.h, warn()) collected instead of printed while a CaptureWarnings lives, for
// tests that check what a load or a render warned about.
#pragma once

#include "core/error.h"

#include <string>
#include <vector>

namespace metamer::test {

class CaptureWarnings {
public:
    CaptureWarnings() : old_(setWarningSink(&CaptureWarnings::sink)) { lines().clear(); }
    ~CaptureWarnings() { setWarningSink(old_); }
    CaptureWarnings(const CaptureWarnings&) = delete;
    CaptureWarnings& operator=(const CaptureWarnings&) = delete;
    // The lines warned since the newest CaptureWarnings was made.
    static std::vector<std::string>& lines() {
        static std::vector<std::string> l;
        return l;
    }
    // Whether some line contains `text`.
    static bool any(const std::string& text) {
        for (const auto& l : lines())
            if (l.find(text) != std::string::npos) return true;
        return false;
    }

private:
    static void sink(const std::string& line) { lines().push_back(line); }
    WarningSink old_;
};

}  // namespace metamer::test
