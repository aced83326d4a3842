#include "scene/overrides.h"

#include "core/error.h"
#include "core/json.h"

#include <algorithm>
#include <cctype>

namespace metamer {

namespace {

std::vector<std::string> splitKey(const std::string& key) {
    std::vector<std::string> parts;
    size_t start = 0;
    while (true) {
        size_t dot = key.find('.', start);
        parts.push_back(key.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
        if (dot == std::string::npos) break;
        start = dot + 1;
    }
    return parts;
}

bool isIndex(const std::string& s) {
    return !s.empty() && s.size() < 10 &&
           std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

// An override as quoted in a message: the whole of a 100 kB value would bury the message.
std::string shortened(const std::string& text) {
    constexpr size_t kShown = 60;
    return text.size() <= kShown ? text : text.substr(0, kShown) + "…";
}

}  // namespace

Override parseOverride(const std::string& text, const std::string& file) {
    Where where{file};
    size_t eq = text.find('=');
    if (eq == std::string::npos)
        failInput(where, "--set {}: expected KEY=VALUE, e.g. lights.0.scale=0.5", text);
    Override o;
    o.text = text;
    o.key = text.substr(0, eq);
    std::string value = text.substr(eq + 1);
    for (const auto& part : splitKey(o.key))
        if (part.empty()) failInput(where, "--set {}: '{}' is not a key path like camera.width", text, o.key);
    // Bare words (illuminants/A) are not JSON; anything that is not JSON is taken as a string.
    int depth = 0;
    auto limitDepth = [&](int, nlohmann::json::parse_event_t event, nlohmann::ordered_json&) {
        using E = nlohmann::json::parse_event_t;
        if (event == E::object_start || event == E::array_start) {
            if (++depth > kMaxJsonDepth)
                failInput(where, "--set {}: the value nests more than {} levels deep", shortened(text), kMaxJsonDepth);
        } else if (event == E::object_end || event == E::array_end) {
            --depth;
        }
        return true;
    };
    try {
        o.value = nlohmann::ordered_json::parse(value, limitDepth);
    } catch (const nlohmann::json::exception&) {
        o.value = value;
    }
    return o;
}

void applyOverride(nlohmann::ordered_json& doc, const Override& o, const std::string& file) {
    auto parts = splitKey(o.key);
    Where where{file};
    nlohmann::ordered_json* node = &doc;
    for (size_t i = 0; i < parts.size(); ++i) {
        const std::string& part = parts[i];
        bool last = i + 1 == parts.size();
        Where here = where.child(part);
        if (node->is_object()) {
            auto it = node->find(part);
            if (it == node->end()) {
                if (last) {
                    (*node)[part] = o.value;
                    return;
                }
                std::vector<std::string> keys;
                for (auto k = node->begin(); k != node->end(); ++k) keys.push_back(k.key());
                std::string near = closestMatch(part, keys);
                if (!near.empty())
                    failInput(here, "--set {}: no such key; did you mean '{}'?", o.text, near);
                failInput(here, "--set {}: no such key in the scene", o.text);
            }
            node = &*it;
        } else if (node->is_array()) {
            if (!isIndex(part))
                failInput(here, "--set {}: '{}' is an array; expected an index 0..{}, got '{}'", o.text,
                          where.key, node->empty() ? 0 : node->size() - 1, part);
            size_t index = std::stoul(part);
            if (index >= node->size())
                failInput(here, "--set {}: no element {}; '{}' has {} element(s)", o.text, index,
                          where.key, node->size());
            node = &(*node)[index];
        } else {
            failInput(where, "--set {}: '{}' is {}, which has no key '{}'", o.text, where.key,
                      jsonTypeName(*node), part);
        }
        where = here;
    }
    *node = o.value;
}

std::vector<Override> applyOverrides(nlohmann::ordered_json& doc, const std::vector<std::string>& overrides,
                                     const std::string& file) {
    std::vector<Override> out;
    for (const auto& text : overrides) {
        out.push_back(parseOverride(text, file));
        applyOverride(doc, out.back(), file);
    }
    return out;
}

}  // namespace metamer
