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

// The first `n` bytes of s from `start`, or fewer so as not to split a UTF-8 character.
static std::string wholeCharacters(const std::string& s, size_t start, size_t n) {
    size_t cut = n;
    while (cut > 0 && (static_cast<unsigned char>(s[start + cut]) & 0xc0) == 0x80) --cut;
    return s.substr(start, cut);
}

// A key path as a message shows it: a part over 80 bytes (a 3 000-character material name) keeps
// its first 40 and says how long it was, so the line stays readable whatever a file names things.
static std::string shownKeyPath(const std::string& key) {
    constexpr size_t kLongPart = 80, kKept = 40;
    std::string out;
    size_t start = 0;
    while (start <= key.size()) {
        size_t dot = key.find('.', start);
        if (dot == std::string::npos) dot = key.size();
        const size_t length = dot - start;
        if (length > kLongPart) {
            out += wholeCharacters(key, start, kKept) + fmt::format("…({} bytes)", length);
        } else {
            out.append(key, start, length);
        }
        if (dot == key.size()) break;
        out += '.';
        start = dot + 1;
    }
    return out;
}

std::string Where::str() const {
    std::string s = file;
    if (line > 0) s += (s.empty() ? "line " : ":") + std::to_string(line);
    if (!key.empty()) s += (s.empty() ? "" : ": ") + shownKeyPath(key);
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
      message_(message),
      text_(composeWhat(where_, message_)) {}

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
    // A typo changes a few characters; beyond a third of the word it is a different word.
    const size_t allowed = std::max<size_t>(2, wanted.size() / 3);
    // Bounded work whatever a hostile file holds: names are words, not megabytes, and a candidate
    // whose length differs by more than `allowed` cannot be within it.
    constexpr size_t kLongest = 128, kMostCandidates = 20000;
    if (wanted.size() > kLongest) return {};
    std::string best;
    size_t bestDistance = SIZE_MAX, looked = 0;
    for (const auto& c : candidates) {
        if (++looked > kMostCandidates) break;
        if (c.size() > kLongest || (c.size() > wanted.size() ? c.size() - wanted.size() : wanted.size() - c.size()) > allowed)
            continue;
        size_t d = editDistance(wanted, c);
        if (d < bestDistance) {
            bestDistance = d;
            best = c;
        }
    }
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

namespace {

constexpr size_t kLongQuote = 160, kKept = 60, kLongLine = 4000;

// Outside quotes, a word (no space in it) over 160 bytes keeps its first 60 and says how long it
// was, as a quoted value does: a library's message naming a 5 000-byte URI, a list of long names.
std::string shortWords(const std::string& s) {
    std::string out;
    for (size_t i = 0; i < s.size();) {
        const size_t end = std::min(s.find(' ', i), s.size());
        size_t length = end - i;
        if (length > kLongQuote) {
            // A list's separator stays after the note: "name…(302 bytes),".
            const bool separator = s[end - 1] == ',' || s[end - 1] == ';';
            length -= separator;
            out += wholeCharacters(s, i, kKept) + fmt::format("…({} bytes)", length) + (separator ? std::string(1, s[end - 1]) : "");
        } else {
            out.append(s, i, length);
        }
        if (end < s.size()) out += ' ';
        i = end + 1;
    }
    return out;
}

// Quoted values ('…') over 160 bytes keep their first 60 and say how long they were, and so do
// long words outside quotes; a line over 4000 bytes keeps its start and end. A message quotes what
// a file holds, which may be megabytes.
std::string shortened(const std::string& s) {
    std::string out;
    size_t i = 0;
    while (i < s.size()) {
        const size_t open = s.find('\'', i);
        if (open == std::string::npos) break;
        const size_t close = s.find('\'', open + 1);
        if (close == std::string::npos) break;
        const size_t length = close - open - 1;
        out += shortWords(s.substr(i, open + 1 - i));
        if (length > kLongQuote) {
            out += wholeCharacters(s, open + 1, kKept) + fmt::format("…' ({} bytes)", length);
        } else {
            out.append(s, open + 1, length + 1);
        }
        i = close + 1;
    }
    if (i < s.size()) out += shortWords(s.substr(i));
    if (out.size() > kLongLine) out = out.substr(0, kLongLine / 2) + fmt::format(" … ({} bytes) … ", out.size()) +
                                      out.substr(out.size() - kLongLine / 4);
    return out;
}

}  // namespace

std::string printableMessage(const std::string& text) {
    const std::string s = shortened(text);
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
