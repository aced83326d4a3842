// A fresh folder per test, removed afterwards: the fixture of every test that writes files
// (engine/io/*_test.cpp). Named after the process and the test, so tests that CTest runs in
// parallel never share one.
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace metamer::test {

class TempFolderTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = std::filesystem::temp_directory_path() /
              fmt::format("metamer-io-{}-{}-{}", ::getpid(), info->test_suite_name(), info->name());
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir);
    }
    void TearDown() override { std::filesystem::remove_all(dir); }

    // The names in `folder` (default: the test's), sorted: what a run left behind.
    std::vector<std::string> namesIn(const std::filesystem::path& folder = {}) const {
        std::vector<std::string> names;
        for (const auto& e : std::filesystem::directory_iterator(folder.empty() ? dir : folder))
            names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }

    std::filesystem::path dir;
};

inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

inline void writeText(const std::filesystem::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary) << text;
}

}  // namespace metamer::test
