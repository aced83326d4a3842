#include "spectral/library.h"

#include "spectral/csv.h"

#include <algorithm>
#include <cstdlib>
#include <dlfcn.h>
#include <unistd.h>

#ifndef METAMER_SOURCE_SPECTRA_DIR
#define METAMER_SOURCE_SPECTRA_DIR ""
#endif

namespace fs = std::filesystem;

namespace metamer {

fs::path SpectrumLibrary::defaultRoot() {
    if (const char* env = std::getenv("METAMER_SPECTRA"); env && *env) return fs::path(env);
    // Beside the code that runs, first: an installed copy (the Python package, a prefix install)
    // must read its own spectra even when the checkout it was built from is still there.
    Dl_info info{};
    std::error_code ec;
    if (dladdr(reinterpret_cast<void*>(&SpectrumLibrary::defaultRoot), &info) && info.dli_fname) {
        const fs::path self = fs::canonical(info.dli_fname, ec);
        if (!ec) {
            const fs::path dir = self.parent_path();
            for (const fs::path& candidate : {dir / "spectra",                       // metamer/_metamer*.so
                                              dir.parent_path() / "spectra",         // metamer/bin/metamer, build/metamer
                                              dir.parent_path() / "share" / "metamer" / "spectra"})  // PREFIX/bin/metamer
                if (fs::is_directory(candidate, ec)) return candidate;
        }
    }
    fs::path source = METAMER_SOURCE_SPECTRA_DIR;
    return source;
}

SpectrumLibrary::SpectrumLibrary(fs::path root) : root_(std::move(root)) {
    // Where the folder came from, for messages: the variable when it is set.
    const char* env = std::getenv("METAMER_SPECTRA");
    const Where where = env && *env && fs::path(env) == root_ ? Where{"", "METAMER_SPECTRA"} : Where{root_.string()};
    const std::string shown = where.file.empty() ? fmt::format("'{}'", root_.string()) : std::string("folder");
    std::error_code ec;
    if (!fs::is_directory(root_, ec))
        failInput(where, "spectra library {} not found{}", shown, where.file.empty() ? "" : " (set METAMER_SPECTRA)");
    // A folder the scan cannot enter is an input error naming it, not a raw filesystem error.
    auto unreadable = [&](const fs::path& p, const std::error_code& e) {
        failInput(where, "spectra library {} cannot be read: {}: {}", shown, p.string(), e.message());
    };
    auto it = fs::recursive_directory_iterator(root_, ec);
    if (ec) unreadable(root_, ec);
    for (; it != fs::recursive_directory_iterator(); it.increment(ec)) {
        if (ec) unreadable(it->path(), ec);
        std::error_code fileEc;
        if (!it->is_regular_file(fileEc) || it->path().extension() != ".csv") continue;
        fs::path rel = it->path().lexically_relative(root_);
        rel.replace_extension();
        names_.push_back(rel.generic_string());
    }
    if (ec) unreadable(root_, ec);
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
