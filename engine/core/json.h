// The JSON conventions every file Metamer writes or reads follows (compare's and bench's
// statistics, tolerance files, scene overrides), and the one parser for every JSON file it reads.
// Tests: engine/compare/compare_test.cpp, engine/compare/tolerance_test.cpp,
// engine/bench/bench_test.cpp.
#pragma once

#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

namespace metamer {

// How deep any JSON Metamer reads may nest: nlohmann's parser recurses, and 100 000 levels crash
// it; no scene, sweep, record or tolerance file needs more than a dozen.
constexpr int kMaxJsonDepth = 64;

// Every JSON document Metamer reads (scenes, sweeps, manifests' lines, job records, tolerance and
// sensor files) goes through this parser. Syntax errors, duplicate keys, numbers beyond a double,
// nesting beyond kMaxJsonDepth levels and UTF-16 text are input errors naming `file`, the line and
// the key path (core/error.h). Never a raw nlohmann exception, never a stack overflow.
nlohmann::ordered_json parseJson(const std::string& text, const std::string& file);

// A number for a JSON file. JSON has no NaN or infinities: a NaN — a value that does not exist
// (not measured, not applicable, undefined as 0/0) — is null, and ±∞ the strings "inf", "-inf".
inline nlohmann::json jsonNumber(double v) {
    if (std::isfinite(v)) return v;
    if (std::isnan(v)) return nullptr;
    return v > 0 ? "inf" : "-inf";
}

// "a string", "an array", … for messages about a value of the wrong type.
template <typename Json>
const char* jsonTypeName(const Json& v) {
    switch (v.type()) {
        case Json::value_t::null: return "null";
        case Json::value_t::boolean: return "a boolean";
        case Json::value_t::string: return "a string";
        case Json::value_t::array: return "an array";
        case Json::value_t::object: return "an object";
        default: return "a number";
    }
}

}  // namespace metamer
