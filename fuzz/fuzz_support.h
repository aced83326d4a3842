// Shared by the libFuzzer targets: a private temporary folder per fuzzing process, quiet warnings,
// and a check that aborts (a finding) when a result breaks the contract its header promises.
#pragma once

#include "core/error.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#ifndef METAMER_SOURCE_DIR
#error "METAMER_SOURCE_DIR must name the source tree (set by CMakeLists.txt)"
#endif

namespace metamer::fuzz {

// A folder of our own under $TMPDIR (or /tmp), removed at exit. Each process of a parallel run
// (-jobs, -workers) gets its own.
inline const std::filesystem::path& workDir() {
    static const std::filesystem::path dir = [] {
        namespace fs = std::filesystem;
        const char* tmp = std::getenv("TMPDIR");
        std::string pattern = (fs::path(tmp && *tmp ? tmp : "/tmp") / "metamer-fuzz-XXXXXX").string();
        if (!mkdtemp(pattern.data())) {
            std::perror("metamer fuzz: mkdtemp");
            std::abort();
        }
        fs::path made = pattern;
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(workDir(), ec);
        });
        return made;
    }();
    return dir;
}

// Warnings are part of normal operation on bad input; printing them would only slow the run.
inline void silenceWarnings() {
    setWarningSink([](const std::string&) {});
}

inline void writeFile(const std::filesystem::path& path, const void* data, size_t size) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out) {
        std::fprintf(stderr, "metamer fuzz: cannot write %s\n", path.c_str());
        std::abort();
    }
}

// A broken promise of the code under test: report it and abort, so libFuzzer keeps the input.
#define METAMER_FUZZ_CHECK(cond)                                                               \
    do {                                                                                       \
        if (!(cond)) {                                                                         \
            std::fprintf(stderr, "metamer fuzz: check failed at %s:%d: %s\n", __FILE__, __LINE__, \
                         #cond);                                                               \
            std::abort();                                                                      \
        }                                                                                      \
    } while (0)

}  // namespace metamer::fuzz
