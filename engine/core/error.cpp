#include "core/error.h"

#include <algorithm>
#include <cstdio>
#include <vector>

namespace metamer {

Where Where::child(const std::string& k) const {
    Where w = *this;
    w.key = key.empty() ? k : key + "." + k;
    return w;
}

Where Where::index(size_t i) const { return child(std::to_string(i)); }

std::string Where::str() const {
    std::string s = file;
    if (line > 0) s += (s.empty() ? "line " : ":") + std::to_string(line);
    if (!key.empty()) s += (s.empty() ? "" : ": ") + key;
    return s;
}

static std::string composeWhat(const Where& where, const std::string& message) {
    std::string w = where.str();
    return w.empty() ? message : w + ": " + message;
}

Error::Error(ExitCode code, Where where, const std::string& message)
    : std::runtime_error(composeWhat(where, message)),
      code_(code),
      where_(std::move(where)),
      message_(message) {}

size_t editDistance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diag = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0u : 1u)});
            diag = up;
        }
    }
    return row[b.size()];
}

std::string closestMatch(const std::string& wanted, const std::vector<std::string>& candidates) {
    std::string best;
    size_t bestDistance = SIZE_MAX;
    for (const auto& c : candidates) {
        size_t d = editDistance(wanted, c);
        if (d < bestDistance) {
            bestDistance = d;
            best = c;
        }
    }
    // A typo changes a few characters; beyond a third of the word it is a different word.
    size_t allowed = std::max<size_t>(2, wanted.size() / 3);
    return bestDistance <= allowed ? best : std::string();
}

static WarningSink gSink = nullptr;

WarningSink setWarningSink(WarningSink sink) {
    WarningSink old = gSink;
    gSink = sink;
    return old;
}

void warn(const Where& where, const std::string& message) {
    std::string line = "warning: " + composeWhat(where, message);
    if (gSink)
        gSink(line);
    else
        std::fprintf(stderr, "%s\n", line.c_str());
}

std::string printableMessage(const std::string& s) {
    std::string out;
    for (size_t i = 0; i < s.size();) {
        auto c = static_cast<unsigned char>(s[i]);
        if (c >= 0x20 && c < 0x7f) {
            out += char(c);
            ++i;
            continue;
        }
        size_t n = c >= 0xc2 && c <= 0xdf ? 2 : c >= 0xe0 && c <= 0xef ? 3 : c >= 0xf0 && c <= 0xf4 ? 4 : 0;
        bool valid = n > 0 && i + n <= s.size();
        for (size_t k = 1; valid && k < n; ++k) valid = (static_cast<unsigned char>(s[i + k]) & 0xc0) == 0x80;
        if (valid) {
            out.append(s, i, n);
            i += n;
        } else {
            out += fmt::format("\\x{:02x}", c);
            ++i;
        }
    }
    return out;
}


}  // namespace metamer
