// Errors that carry their context: the file, the key path inside it (or a line), and what was
// expected. Every user-facing failure in Metamer is one of these, so the CLI can print one line
// and choose an exit code without knowing which stage failed.
// Tests: every bad-input test (tests/bad_inputs_test.cpp), engine/scene/scene_json_test.cpp.
#pragma once

#include <fmt/format.h>

#include <stdexcept>
#include <utility>
#include <string>
#include <vector>

namespace metamer {

// Exit codes of the `metamer` tool (documented in README.md).
enum class ExitCode : int {
    Ok = 0,
    Failure = 1,    // a runtime failure that is not the user's input (I/O error, driver error)
    BadInput = 2,   // the scene, a spectrum file or the command line is wrong
    NoDevice = 3,   // no usable Vulkan device
    NoDisplay = 4,  // `metamer preview`: no display to open a window on (no DISPLAY, GLFW cannot start)
};

// Where in the user's input something went wrong. Any field may be empty.
struct Where {
    std::string file;  // path as the user gave it (or as resolved)
    std::string key;   // JSON key path, e.g. "materials.skin.diffuse"
    int line = 0;      // 1-based line number for line-oriented files (CSV); 0 = none

    Where child(const std::string& k) const;       // "a.b" + "c" -> "a.b.c"
    Where index(size_t i) const;                   // "a.b" + 2   -> "a.b.2"
    std::string str() const;                       // "file:line: key" (parts omitted when empty)
};

class Error : public std::runtime_error {
public:
    Error(ExitCode code, Where where, const std::string& message);
    ExitCode code() const { return code_; }
    const Where& where() const { return where_; }
    const std::string& message() const { return message_; }
    // "where: message" whole: what() is a C string and would end at a NUL byte the message quotes.
    const std::string& text() const { return text_; }

private:
    ExitCode code_;
    Where where_;
    std::string message_;
    std::string text_;
};

// A file the user named that does not exist: bad input (exit code 2) like any other, told apart
// so that the Python module can raise it as FileNotFoundError too (requireRegularFile throws it).
class NotFoundError : public Error {
public:
    NotFoundError(Where where, const std::string& message) : Error(ExitCode::BadInput, std::move(where), message) {}
};

// Bad user input: exit code 2.
template <typename... Args>
[[noreturn]] void failInput(const Where& where, fmt::format_string<Args...> f, Args&&... args) {
    throw Error(ExitCode::BadInput, where, fmt::format(f, std::forward<Args>(args)...));
}

// Runtime failure not caused by the input: exit code 1.
template <typename... Args>
[[noreturn]] void failRuntime(fmt::format_string<Args...> f, Args&&... args) {
    throw Error(ExitCode::Failure, Where{}, fmt::format(f, std::forward<Args>(args)...));
}

// Edit distance, for "did you mean ...?" suggestions.
size_t editDistance(const std::string& a, const std::string& b);

// The closest candidate to `wanted` if it is close enough to be a plausible typo, else "".
std::string closestMatch(const std::string& wanted, const std::vector<std::string>& candidates);

// Messages quote what the user's files contain (a binary file named .csv, a JSON string with
// invalid UTF-8, a line with a carriage return): the message as one printable line, control
// characters and bytes that are not UTF-8 written as \xNN (a NUL as \x00), quoted values over 160
// bytes shortened with their length, the line kept under about 4000 bytes. What the CLI and the
// Python module print.
std::string printableMessage(const std::string& s);

// Warnings go to stderr with their context; tests can capture them.
void warn(const Where& where, const std::string& message);
// Route warnings elsewhere (nullptr restores stderr). Returns the previous sink.
using WarningSink = void (*)(const std::string& line);
WarningSink setWarningSink(WarningSink sink);

}  // namespace metamer
