// Where Metamer keeps what it computes once and reuses across processes (the Vulkan pipeline
// cache, the hemisphere lights' lobe tables): the folder the environment variable `variable`
// names ("off": none), else $XDG_CACHE_HOME/metamer, else ~/.cache/metamer; empty when disabled or
// when there is no home. Tests: core/cache_folder_test.cpp.
#pragma once

#include <filesystem>

namespace metamer {

std::filesystem::path cacheFolder(const char* variable);

}  // namespace metamer
