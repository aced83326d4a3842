#include "scene/json_values.h"

#include "core/json.h"
#include "scene/overrides.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>
#include <sstream>

namespace metamer::json_read {

namespace {


// ---------------------------------------------------------------------------------------------
// Parsing: nlohmann's parser reports syntax errors by byte offset and ignores duplicate keys, so
// a SAX handler follows the key path as it parses, to reject duplicates and to say where an error
// happened, and hands every event on to nlohmann's own DOM builder. (Its callback parser would do
// the same, but scans a container's elements at every object's end: 200 000 objects took 11 s.)

class PathTracker {
public:
    PathTracker(std::string file, Json& result) : file_(std::move(file)), dom_(result) {}

    // The key path being parsed; its first `levels` parts when given (a path 64 levels deep is
    // mostly noise).
    std::string path(size_t levels = SIZE_MAX) const {
        std::string p;
        for (const auto& f : stack_) {
            if (levels-- == 0) return p + ".…";
            std::string part = f.array ? std::to_string(f.count) : f.key;
            if (part.empty()) break;
            p += (p.empty() ? "" : ".") + part;
        }
        return p;
    }

    // nlohmann's SAX interface.
    bool null() { return value(dom_.null()); }
    bool boolean(bool v) { return value(dom_.boolean(v)); }
    bool number_integer(Json::number_integer_t v) { return value(dom_.number_integer(v)); }
    bool number_unsigned(Json::number_unsigned_t v) { return value(dom_.number_unsigned(v)); }
    bool number_float(Json::number_float_t v, const Json::string_t& text) { return value(dom_.number_float(v, text)); }
    bool string(Json::string_t& v) { return value(dom_.string(v)); }
    bool binary(Json::binary_t& v) { return value(dom_.binary(v)); }
    bool start_object(std::size_t n) { return open(false) && dom_.start_object(n); }
    bool start_array(std::size_t n) { return open(true) && dom_.start_array(n); }
    bool key(Json::string_t& k) {
        Frame& f = stack_.back();
        f.key = k;
        if (!f.keys.insert(f.key).second)
            failInput(Where{file_, path()}, "duplicate key (the later value would silently replace the earlier)");
        return dom_.key(k);
    }
    bool end_object() { return close() && dom_.end_object(); }
    bool end_array() { return close() && dom_.end_array(); }
    template <typename Exception>
    bool parse_error(std::size_t position, const std::string& token, const Exception& e) {
        return dom_.parse_error(position, token, e);  // throws e
    }

private:
    static constexpr size_t kShownDepth = 6;

    struct Frame {
        bool array = false;
        std::string key;  // the member being parsed; "" between members
        size_t count = 0;  // elements completed so far = index of the one being parsed
        std::set<std::string> keys;
    };

    bool open(bool array) {
        if (stack_.size() >= size_t(kMaxJsonDepth))
            failInput(Where{file_, path(kShownDepth)}, "the JSON nests more than {} levels deep", kMaxJsonDepth);
        stack_.push_back({array});
        return true;
    }
    bool close() {
        stack_.pop_back();
        finishValue();
        return true;
    }
    bool value(bool ok) {
        finishValue();
        return ok;
    }
    void finishValue() {
        if (stack_.empty()) return;
        if (stack_.back().array)
            ++stack_.back().count;
        else
            stack_.back().key.clear();
    }

    std::string file_;
    std::vector<Frame> stack_;
    nlohmann::detail::json_sax_dom_parser<Json> dom_;
};

// 1-based line and column of a 0-based byte offset.
std::pair<int, int> lineColumn(const std::string& text, size_t offset) {
    offset = std::min(offset, text.size());
    int line = 1;
    size_t lineStart = 0;
    for (size_t i = 0; i < offset; ++i)
        if (text[i] == '\n') {
            ++line;
            lineStart = i + 1;
        }
    return {line, static_cast<int>(offset - lineStart) + 1};
}

// A file saved as UTF-16 (a byte-order mark, or a NUL in every other byte of its start) is named
// as such, rather than as a syntax error at column 1.
void refuseUtf16(const std::string& text, const std::string& file) {
    const bool bom = text.size() >= 2 && ((text[0] == '\xFF' && text[1] == '\xFE') || (text[0] == '\xFE' && text[1] == '\xFF'));
    const size_t head = std::min<size_t>(text.size(), 64);
    size_t nuls = 0;
    for (size_t i = 0; i < head; ++i) nuls += text[i] == '\0';
    if (bom || (head >= 4 && nuls * 3 >= head))
        failInput(Where{file}, "is not UTF-8: it looks like UTF-16{} (save it as UTF-8)",
                  bom ? " (it starts with a UTF-16 byte-order mark)" : "");
}

}  // namespace

Json parseJson(const std::string& text, const std::string& file) {
    refuseUtf16(text, file);
    Json result;
    PathTracker tracker(file, result);
    try {
        Json::sax_parse(text, &tracker, nlohmann::json::input_format_t::json, /*strict=*/true,
                        /*ignore_comments=*/false);
        return result;
    } catch (const nlohmann::json::parse_error& e) {
        // nlohmann's message reads "[json.exception.parse_error.101] parse error at line L,
        // column C: what"; keep only "what" and compute the position ourselves.
        std::string what = e.what();
        if (size_t c = what.find("column "); c != std::string::npos)
            if (size_t colon = what.find(": ", c); colon != std::string::npos) what = what.substr(colon + 2);
        auto [line, column] = lineColumn(text, e.byte == 0 ? 0 : e.byte - 1);
        failInput(Where{file, tracker.path(), line}, "JSON syntax error at column {}: {}", column, what);
    } catch (const nlohmann::json::out_of_range& e) {
        // A number too large for a double (1e999). Find the literal for the line number.
        std::string what = e.what();
        std::string literal;
        if (size_t q = what.find('\''); q != std::string::npos) {
            size_t q2 = what.find('\'', q + 1);
            if (q2 != std::string::npos) literal = what.substr(q + 1, q2 - q - 1);
        }
        int line = 0;
        if (!literal.empty())
            if (size_t at = text.find(literal); at != std::string::npos) line = lineColumn(text, at).first;
        failInput(Where{file, tracker.path(), line}, "number {} is out of the range of a double", literal);
    }
}

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
