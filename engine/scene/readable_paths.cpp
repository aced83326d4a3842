#include "scene/readable_paths.h"

namespace fs = std::filesystem;

namespace metamer {

namespace {

// Absolute, symlinks resolved as far as the path exists, the rest normalized lexically. A path
// that cannot be resolved (permissions) is judged by its lexical form, which is what the OS would
// be asked to open.
fs::path resolved(const fs::path& p) {
    std::error_code ec;
    fs::path abs = fs::absolute(p, ec);
    if (ec) abs = p;
    fs::path c = fs::weakly_canonical(abs, ec);
    return ec ? abs.lexically_normal() : c;
}

}  // namespace

bool isInsideFolder(const fs::path& path, const fs::path& root) {
    fs::path p = resolved(path), r = resolved(root);
    // Component by component: a string prefix would put /data/scenes2 inside /data/scenes. Empty
    // components come from a trailing separator and carry no name.
    auto pi = p.begin();
    for (auto ri = r.begin(); ri != r.end(); ++ri) {
        if (ri->empty()) continue;
        while (pi != p.end() && pi->empty()) ++pi;
        if (pi == p.end() || *pi != *ri) return false;
        ++pi;
    }
    return true;
}

ReadablePaths ReadablePaths::anywhere() { return ReadablePaths{}; }

ReadablePaths ReadablePaths::forScene(const fs::path& sceneFile, const fs::path& libraryRoot, bool allowOutside) {
    ReadablePaths r;
    if (allowOutside) return r;
    r.restricted_ = true;
    fs::path dir = sceneFile.parent_path();
    r.roots_.push_back(resolved(dir.empty() ? fs::path(".") : dir));
    if (!libraryRoot.empty()) r.roots_.push_back(resolved(libraryRoot));
    return r;
}

bool ReadablePaths::allows(const fs::path& path) const {
    if (!restricted_) return true;
    for (const auto& root : roots_)
        if (isInsideFolder(path, root)) return true;
    return false;
}

std::string ReadablePaths::refusal(const fs::path& path, const std::string& what, const std::string& shown) const {
    std::string real = resolved(path).string();
    std::string folders;
    for (size_t i = 0; i < roots_.size(); ++i)
        folders += (i == 0 ? "" : i + 1 == roots_.size() ? " and " : ", ") + roots_[i].string();
    return fmt::format("{} '{}'{} is outside the folders a scene may read ({}); pass --allow-outside-paths "
                       "to read it",
                       what, shown, real == shown ? "" : " (" + real + ")", folders);
}

void ReadablePaths::check(const fs::path& path, const Where& where, const std::string& what,
                          const std::string& shown) const {
    if (!allows(path)) failInput(where, "{}", refusal(path, what, shown));
}

}  // namespace metamer
