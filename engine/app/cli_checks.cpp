#include "app/cli_checks.h"

#include "core/error.h"
#include "core/file_reads.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <limits>
#include <cstdlib>
#include <filesystem>
#include <string_view>

namespace metamer {

namespace {

bool numericType(const std::string& type) {
    return type.find("FLOAT") != std::string::npos || type.find("INT") != std::string::npos ||
           type.find("NUMBER") != std::string::npos;
}

// Whether `text` reads as a number that is NaN or infinite ("nan", "-inf", "1e999").
bool nonFiniteNumber(const std::string& text) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    return end != text.c_str() && *end == '\0' && !std::isfinite(v);
}

// Whether `text` is a whole number in decimal digits that fits 64 bits unsigned. CLI11 reads
// "-1" into an unsigned option as 2⁶⁴ − 1 and "2⁶⁴" as 2⁶⁴ − 1: both silently.
bool wholeUnsigned(const std::string& text) {
    if (text.empty() || text.size() > 20 || !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
        return false;
    errno = 0;
    std::strtoull(text.c_str(), nullptr, 10);
    return errno != ERANGE;
}

void checkOptions(const CLI::App& app) {
    for (const CLI::Option* o : app.get_options()) {
        if (o->count() == 0) continue;
        const std::string name = o->get_name();
        for (const std::string& value : o->results()) {
            if (value.empty() && !o->get_type_name().empty())
                failInput(Where{"", name}, "expected a value, got an empty string");
            if (numericType(o->get_type_name()) && nonFiniteNumber(value))
                failInput(Where{"", name}, "expected a finite number, got '{}'", value);
            if (o->get_type_name().find("UINT") != std::string::npos && !wholeUnsigned(value))
                failInput(Where{"", name}, "'{}' is not a whole number from 0 to {}", value,
                          std::numeric_limits<uint64_t>::max());
        }
    }
    for (const CLI::App* sub : app.get_subcommands({}))
        if (sub->parsed()) checkOptions(*sub);
}

CLI::Validator numberAbove(bool strict, const std::string& unit) {
    return CLI::Validator(
        [strict, unit](std::string& text) -> std::string {
            char* end = nullptr;
            const double v = std::strtod(text.c_str(), &end);
            if (end == text.c_str() || *end != '\0') return "'" + text + "' is not a number";
            if (!std::isfinite(v)) return "expected a finite number, got '" + text + "'";
            if (strict ? v > 0 : v >= 0) return "";
            return "'" + text + "': expected a number " + (strict ? "above 0" : "of 0 or more") +
                   (unit.empty() ? "" : " (" + unit + ")");
        },
        strict ? "POSITIVE" : "NONNEGATIVE");
}

}  // namespace

CLI::Validator outputFolder() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            namespace fs = std::filesystem;
            std::error_code ec;
            const fs::file_status st = fs::status(text, ec);
            if (!fs::exists(st) || fs::is_directory(st)) return "";
            return "'" + text + "' is " + (fs::is_regular_file(st) ? "a file" : specialFileKind(st)) +
                   ", not a folder; the outputs go into a folder (created if missing)";
        },
        "FOLDER");
}

void checkVerb(const CLI::App& app, int argc, char** argv) {
    if (argc < 2 || argv[1][0] == '-') return;
    const std::string verb = argv[1];
    std::vector<std::string> verbs;
    for (const CLI::App* sub : app.get_subcommands({})) {
        verbs.push_back(sub->get_name());
        if (sub->get_name() == verb) return;
    }
    const std::string near = closestMatch(verb, verbs);
    std::string list;
    for (const auto& v : verbs) list += (list.empty() ? "" : ", ") + v;
    failInput(Where{}, "'{}' is not a command{}; the commands are {} (metamer --help)",
              printableMessage(verb.size() > 40 ? verb.substr(0, 40) + "…" : verb),
              near.empty() ? "" : fmt::format(" (did you mean '{}'?)", near), list);
}

void checkParsedValues(const CLI::App& app) { checkOptions(app); }

void failUnexpectedArguments(const CLI::App& app) {
    // The command that was given: the deepest subcommand parsed.
    const CLI::App* at = &app;
    while (!at->get_subcommands().empty()) at = at->get_subcommands().front();
    const std::string command = at == &app ? "metamer" : "metamer " + at->get_name();
    const std::vector<std::string> extras = app.remaining(true);
    std::string first = extras.empty() ? "" : extras.front();
    for (const std::string& e : extras)
        if (e.size() > 1 && e[0] == '-') {
            first = e;
            break;
        }
    if (first.size() > 1 && first[0] == '-') {
        const std::string typed = first.substr(0, first.find('='));
        std::vector<std::string> names;
        for (const CLI::App* a = at; a; a = a->get_parent())
            for (const CLI::Option* o : a->get_options()) {
                if (o->get_group().empty()) continue;  // hidden
                for (const std::string& l : o->get_lnames()) names.push_back("--" + l);
                for (const std::string& s : o->get_snames()) names.push_back("-" + s);
            }
        const std::string near = closestMatch(typed, names);
        failInput(Where{"", printableMessage(typed)}, "not an option of {}{}; {} --help lists them", command,
                  near.empty() ? "" : fmt::format(" (did you mean {}?)", near), command);
    }
    failInput(Where{}, "'{}' was not expected: {} takes {}; {} --help says more", printableMessage(first), command,
              at->get_options([](const CLI::Option* o) { return o->get_positional(); }).empty()
                  ? "no positional argument"
                  : "fewer positional arguments",
              command);
}

CLI::Validator positiveNumber(const std::string& unit) { return numberAbove(true, unit); }
CLI::Validator nonNegativeNumber() { return numberAbove(false, ""); }

}  // namespace metamer
