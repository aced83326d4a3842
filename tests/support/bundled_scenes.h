// The scenes Metamer ships (scenes/*.json, sorted), for the tests that hold every one of them to
// something: tests/frame_barriers_test.cpp, tests/ground_truth_test.cpp.
#pragma once

#include <algorithm>
#include <filesystem>
#include <vector>

namespace metamer::test {

inline std::vector<std::filesystem::path> bundledScenes() {
    std::vector<std::filesystem::path> scenes;
    for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(METAMER_SOURCE_DIR) / "scenes"))
        if (e.path().extension() == ".json") scenes.push_back(e.path());
    std::sort(scenes.begin(), scenes.end());
    return scenes;
}

}  // namespace metamer::test
