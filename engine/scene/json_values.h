// Reading a scene's JSON: the parser, which follows the key path as it parses (to refuse
// duplicate keys and to say on which line and under which key an error is), and typed access
// whose errors name the file, the key, what was expected and what was found. Used by
// scene/scene_json.cpp, scene/scene_reader.cpp and the material readers (scene/material_readers.h).
// Tests: scene/scene_json_test.cpp, tests/bad_inputs_test.cpp.
#pragma once

#include "core/json.h"
#include "core/error.h"

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <string>
#include <vector>

namespace metamer::json_read {

using Json = nlohmann::ordered_json;

// The one JSON parser (core/json.h), under the name the scene readers have always used.
using metamer::parseJson;

// "an array of 3", "a string", … for messages.
std::string describe(const Json& v);
// A list for a message: at most 20 names, then how many more.
std::string join(const std::vector<std::string>& items);

const Json& asObject(const Json& v, const Where& w);
const Json& asArray(const Json& v, const Where& w);

// A typo (closestMatch), or else the one allowed key that the given key abbreviates or extends.
std::string suggestKey(const std::string& key, const std::vector<std::string>& allowed);
// Rejects keys outside `allowed`, suggesting the nearest one. `elsewhere` lists keys that are
// valid in a sibling form of the object (an orthographic camera's height_m on a perspective one).
void checkKeys(const Json& obj, const Where& w, const std::vector<std::string>& allowed, const std::string& form = "",
               const std::vector<std::string>& elsewhere = {});

const Json* find(const Json& obj, const char* key);
const Json& require(const Json& obj, const Where& w, const char* key, const char* what);

double number(const Json& v, const Where& w);  // finite
// A number in [lo, hi], or (lo, hi] etc. when the ends are open.
double numberIn(const Json& v, const Where& w, double lo, double hi, bool loOpen, bool hiOpen, const char* units = "");
int integerIn(const Json& v, const Where& w, int lo, int hi);
std::string string(const Json& v, const Where& w);
// A unit vector from a non-zero one, normalized without overflow or underflow.
glm::dvec3 nonZeroDirection(const Json& v, const Where& w);
bool isFinite(const glm::dvec3& v);
// One of `choices`, with a suggestion when it is a typo.
std::string choice(const Json& v, const Where& w, const std::vector<std::string>& choices);
bool endsWithCsv(const std::string& s);

// An array of N numbers.
template <int N>
glm::vec<N, double> vector(const Json& v, const Where& w) {
    if (!v.is_array() || v.size() != N || !std::all_of(v.begin(), v.end(), [](const Json& e) { return e.is_number(); }))
        failInput(w, "expected an array of {} numbers, got {}", N, describe(v));
    glm::vec<N, double> out;
    for (int i = 0; i < N; ++i) out[i] = number(v[i], w.index(i));
    return out;
}

}  // namespace metamer::json_read
