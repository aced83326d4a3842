// The spectra library: the CSV files under spectra/, addressed by name without extension,
// e.g. "illuminants/D65" -> spectra/illuminants/D65.csv.
#pragma once

#include "spectral/spectrum.h"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace metamer {

class SpectrumLibrary {
public:
    // The library root: $METAMER_SPECTRA if set, else the first folder found beside the binary or
    // shared object this code is linked into (D = its folder): D/spectra (the Python package),
    // D/../spectra (the package's bin/metamer; build/metamer finds the source tree's), or
    // D/../share/metamer/spectra (an installed prefix); else the source tree's spectra/ (compiled in).
    static std::filesystem::path defaultRoot();

    explicit SpectrumLibrary(std::filesystem::path root = defaultRoot());

    const std::filesystem::path& root() const { return root_; }
    bool contains(const std::string& name) const;
    std::vector<std::string> names() const;  // all "folder/name" entries, sorted

    // Loads (and caches) a library spectrum. Unknown names throw an input error at `where`
    // with a "did you mean" suggestion.
    const Spectrum& get(const std::string& name, const Where& where) const;

    // A suggestion for an unknown name: "colorchecker/dark_skin", or "" when nothing is close.
    std::string suggest(const std::string& name) const;

private:
    std::filesystem::path root_;
    std::vector<std::string> names_;
    mutable std::map<std::string, Spectrum> cache_;
};

}  // namespace metamer
