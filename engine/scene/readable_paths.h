// Which files a scene may make Metamer read. A scene file can come from anyone (a colleague, a
// download, a paper's supplement), and every path in it — CSV spectra, glTF meshes and the
// buffers and images those reference, a csv: detector — is a read of the user's disk. By default
// a scene may read only inside its own folder tree and the spectra library;
// `--allow-outside-paths` lifts that (docs/scene-format.md, "Paths and what a scene may read").
#pragma once

#include "core/error.h"

#include <filesystem>
#include <string>
#include <vector>

namespace metamer {

// True when `path` is `root` or lies below it, compared component by component after both are
// made absolute and weakly canonical (symlinks followed as far as the path exists, "." and ".."
// removed). So /data/scenes2 is not inside /data/scenes, and a symlink inside root that points
// elsewhere is outside.
bool isInsideFolder(const std::filesystem::path& path, const std::filesystem::path& root);

class ReadablePaths {
public:
    // No restriction: every path is readable (what --allow-outside-paths asks for, and what code
    // loading trusted files of its own uses).
    static ReadablePaths anywhere();

    // The folder tree of `sceneFile` (the folder its relative paths resolve against) and the
    // spectra library's folder; or anywhere, when `allowOutside`.
    static ReadablePaths forScene(const std::filesystem::path& sceneFile, const std::filesystem::path& libraryRoot,
                                  bool allowOutside);

    bool restricted() const { return restricted_; }
    bool allows(const std::filesystem::path& path) const;

    // An input error at `where` when `path` may not be read: names `shown` (the path as the
    // scene wrote it), where it really leads, the allowed folders and how to allow it. `what`
    // says what the file is ("spectrum file", "mesh file").
    void check(const std::filesystem::path& path, const Where& where, const std::string& what,
               const std::string& shown) const;

    // The message of such an error, without the location (for errors raised inside a reader).
    std::string refusal(const std::filesystem::path& path, const std::string& what, const std::string& shown) const;

private:
    bool restricted_ = false;
    std::vector<std::filesystem::path> roots_;  // absolute and weakly canonical
};

}  // namespace metamer
