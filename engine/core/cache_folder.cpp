#include "core/cache_folder.h"

#include <cstdlib>
#include <string_view>

namespace metamer {

std::filesystem::path cacheFolder(const char* variable) {
    namespace fs = std::filesystem;
    if (const char* v = std::getenv(variable); v && *v) return std::string_view(v) == "off" ? fs::path() : fs::path(v);
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return fs::path(x) / "metamer";
    if (const char* h = std::getenv("HOME"); h && *h) return fs::path(h) / ".cache" / "metamer";
    return {};
}

}  // namespace metamer
