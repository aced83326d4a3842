#include "scene/json_values.h"

#include "core/json.h"
#include "scene/overrides.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>
#include <sstream>

namespace metamer::json_read {

// ---------------------------------------------------------------------------------------------
// Typed access with messages that name what was expected and what was found.

std::string describe(const Json& v) {
    if (v.is_array()) return v.empty() ? "an empty array" : fmt::format("an array of {}", v.size());
    return jsonTypeName(v);
}

// A list for a message: at most 20 names, then how many more (a scene may define thousands).
std::string join(const std::vector<std::string>& items) {
    constexpr size_t kShown = 20;
    std::string s;
    for (size_t i = 0; i < items.size() && i < kShown; ++i) s += (s.empty() ? "" : ", ") + items[i];
    if (items.size() > kShown) s += fmt::format(" and {} more", items.size() - kShown);
    return s;
}

const Json& asObject(const Json& v, const Where& w) {
    if (!v.is_object()) failInput(w, "expected an object, got {}", describe(v));
    return v;
}

const Json& asArray(const Json& v, const Where& w) {
    if (!v.is_array()) failInput(w, "expected an array, got {}", describe(v));
    return v;
}

// A typo (closestMatch), or else the one allowed key that the given key abbreviates or extends:
// "fov" -> "fov_y_deg", "radius_m" -> "radius".
std::string suggestKey(const std::string& key, const std::vector<std::string>& allowed) {
    std::string near = closestMatch(key, allowed);
    if (!near.empty() || key.size() < 3) return near;
    std::vector<std::string> prefixed;
    for (const auto& a : allowed)
        if (a.size() >= 3 && (a.rfind(key, 0) == 0 || key.rfind(a, 0) == 0)) prefixed.push_back(a);
    return prefixed.size() == 1 ? prefixed.front() : std::string();
}

// Rejects keys outside `allowed`, suggesting the nearest one. `elsewhere` lists keys that are
// valid in a sibling form of the object (an orthographic camera's height_m on a perspective
// one), to say so rather than "unknown".
void checkKeys(const Json& obj, const Where& w, const std::vector<std::string>& allowed, const std::string& form,
               const std::vector<std::string>& elsewhere) {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
        const std::string& key = it.key();
        if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
        Where at = w.child(key);
        std::string forWhat = form.empty() ? "" : " for " + form;
        if (std::find(elsewhere.begin(), elsewhere.end(), key) != elsewhere.end())
            failInput(at, "key not allowed{}; allowed keys are {}", forWhat, join(allowed));
        std::string near = suggestKey(key, allowed);
        if (!near.empty()) failInput(at, "unknown key{}; did you mean '{}'?", forWhat, near);
        failInput(at, "unknown key{}; allowed keys are {}", forWhat, join(allowed));
    }
}

const Json* find(const Json& obj, const char* key) {
    auto it = obj.find(key);
    return it == obj.end() ? nullptr : &*it;
}

const Json& require(const Json& obj, const Where& w, const char* key, const char* what) {
    const Json* v = find(obj, key);
    if (!v) failInput(w.child(key), "missing required key ({})", what);
    return *v;
}

double number(const Json& v, const Where& w) {
    if (!v.is_number()) failInput(w, "expected a number, got {}", describe(v));
    double x = v.get<double>();
    if (!std::isfinite(x)) failInput(w, "expected a finite number");
    return x;
}

// A number in [lo, hi], or (lo, hi] etc. when the ends are open.
double numberIn(const Json& v, const Where& w, double lo, double hi, bool loOpen, bool hiOpen, const char* units) {
    double x = number(v, w);
    bool ok = (loOpen ? x > lo : x >= lo) && (hiOpen ? x < hi : x <= hi);
    if (!ok && std::isinf(hi)) failInput(w, "must be {} {:g}, got {:g}{}", loOpen ? ">" : "≥", lo, x, units);
    if (!ok)
        failInput(w, "{:g}{} is outside the allowed range {}{:g}, {:g}{}", x, units, loOpen ? "(" : "[", lo, hi,
                  hiOpen ? ")" : "]");
    return x;
}

int integerIn(const Json& v, const Where& w, int lo, int hi) {
    if (!v.is_number()) failInput(w, "expected an integer, got {}", describe(v));
    double x = v.get<double>();
    if (!std::isfinite(x) || x != std::floor(x)) failInput(w, "expected an integer, got {:g}", x);
    if (x < lo || x > hi) failInput(w, "{:g} is outside the allowed range {}..{}", x, lo, hi);
    return static_cast<int>(x);
}

std::string string(const Json& v, const Where& w) {
    if (!v.is_string()) failInput(w, "expected a string, got {}", describe(v));
    return v.get<std::string>();
}

glm::dvec3 nonZeroDirection(const Json& v, const Where& w) {
    glm::dvec3 d = vector<3>(v, w);
    // Divided by the largest component first, so that the length neither overflows ([1e200, 1e200,
    // 0]) nor underflows to 0 (subnormal components) for a direction that is a valid one.
    double big = std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)});
    if (!(big > 0.0)) failInput(w, "a direction must not be the zero vector");
    d /= big;
    return d / glm::length(d);
}

bool isFinite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// One of `choices`, with a suggestion when it is a typo.
std::string choice(const Json& v, const Where& w, const std::vector<std::string>& choices) {
    std::string s = string(v, w);
    if (std::find(choices.begin(), choices.end(), s) != choices.end()) return s;
    std::string near = closestMatch(s, choices);
    if (!near.empty()) failInput(w, "'{}' is not one of {}; did you mean '{}'?", s, join(choices), near);
    failInput(w, "'{}' is not one of {}", s, join(choices));
}

bool endsWithCsv(const std::string& s) {
    if (s.size() < 4) return false;
    std::string ext = s.substr(s.size() - 4);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext == ".csv";
}

}  // namespace metamer::json_read
