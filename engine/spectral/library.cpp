#include "spectral/library.h"

#include "spectral/csv.h"

#include <algorithm>
#include <cstdlib>
#include <unistd.h>

#ifndef METAMER_SOURCE_SPECTRA_DIR
#define METAMER_SOURCE_SPECTRA_DIR ""
#endif

namespace fs = std::filesystem;

namespace metamer {

fs::path SpectrumLibrary::defaultRoot() {
    if (const char* env = std::getenv("METAMER_SPECTRA"); env && *env) return fs::path(env);
    fs::path source = METAMER_SOURCE_SPECTRA_DIR;
    if (!source.empty() && fs::is_directory(source)) return source;
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        fs::path installed = exe.parent_path().parent_path() / "share" / "metamer" / "spectra";
        if (fs::is_directory(installed)) return installed;
    }
    return source;
}

SpectrumLibrary::SpectrumLibrary(fs::path root) : root_(std::move(root)) {
    std::error_code ec;
    if (!fs::is_directory(root_, ec))
        failInput(Where{root_.string()}, "spectra library folder not found (set METAMER_SPECTRA)");
    for (auto it = fs::recursive_directory_iterator(root_, ec); it != fs::recursive_directory_iterator();
         it.increment(ec)) {
        if (ec) break;
        if (!it->is_regular_file() || it->path().extension() != ".csv") continue;
        fs::path rel = fs::relative(it->path(), root_);
        rel.replace_extension();
        names_.push_back(rel.generic_string());
    }
    std::sort(names_.begin(), names_.end());
}

bool SpectrumLibrary::contains(const std::string& name) const {
    return std::binary_search(names_.begin(), names_.end(), name);
}

std::vector<std::string> SpectrumLibrary::names() const { return names_; }

std::string SpectrumLibrary::suggest(const std::string& name) const {
    // Compare within the same folder first (a typo in the file name), then across the library.
    auto slash = name.find('/');
    if (slash != std::string::npos) {
        std::string folder = name.substr(0, slash + 1);
        std::vector<std::string> sameFolder;
        for (const auto& n : names_)
            if (n.compare(0, folder.size(), folder) == 0) sameFolder.push_back(n.substr(folder.size()));
        std::string m = closestMatch(name.substr(slash + 1), sameFolder);
        if (!m.empty()) return folder + m;
    }
    return closestMatch(name, names_);
}

const Spectrum& SpectrumLibrary::get(const std::string& name, const Where& where) const {
    if (auto it = cache_.find(name); it != cache_.end()) return it->second;
    if (!contains(name)) {
        std::string s = suggest(name);
        if (!s.empty()) failInput(where, "no spectrum '{}'; did you mean '{}'?", name, s);
        failInput(where, "no spectrum '{}' in the library ({}) and no such file", name, root_.string());
    }
    Spectrum sp = readSpectrumCsv(root_ / (name + ".csv"));
    sp.source = name;
    return cache_.emplace(name, std::move(sp)).first->second;
}

}  // namespace metamer
