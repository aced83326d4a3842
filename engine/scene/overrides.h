// `--set KEY=VALUE` overrides, applied to a scene's JSON before it is interpreted, so an override
// is checked exactly like the file's own value.
// Tests: engine/scene/overrides_test.cpp, tests/cli_test.cpp.
#pragma once

#include "core/json.h"
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace metamer {

// How deeply a --set value may nest: kMaxJsonDepth (core/json.h), as a scene.

struct Override {
    std::string text;  // as given: "lights.0.scale=0.5"
    std::string key;   // "lights.0.scale"
    nlohmann::ordered_json value;
};

// Splits KEY=VALUE at the first '='. VALUE is JSON when it parses as JSON (0.5, true, [1,2,3],
// {"a":1}, "quoted"), otherwise the plain string (illuminants/A). Errors name `file` and the
// override.
Override parseOverride(const std::string& text, const std::string& file);

// Sets doc at the override's key path. Segments are object keys or array indices; every segment
// but the last must exist. The last may name a new key in an existing object (the scene loader
// then judges whether that key is allowed) but not a new array element.
void applyOverride(nlohmann::ordered_json& doc, const Override& o, const std::string& file);

// parseOverride + applyOverride for each, in order; returns them for error attribution.
std::vector<Override> applyOverrides(nlohmann::ordered_json& doc, const std::vector<std::string>& overrides,
                                     const std::string& file);

}  // namespace metamer
