#include "render/cube_formats.h"

#include "io/envi_cube.h"
#include "io/hdf5_cube.h"
#include "io/spectral_exr.h"

#include <algorithm>

namespace metamer {

namespace {

std::vector<CubeContainer> makeTable() {
    std::vector<CubeContainer> t;
    t.push_back(CubeContainer{
        "exr", {}, "exr", {"exr"}, ".exr",
        [](const std::string&, const std::string& options, const Where&, std::string& out) {
            out.clear();
            return options.empty();
        },
        [](const std::filesystem::path& path, int width, int height, const Grid& grid, const CubeWriteSettings& s) {
            ExrWriteOptions o;
            o.half = s.half;
            o.compression = s.compression;
            o.extraAttributes = s.provenance;
            o.preview = s.preview;
            o.component = s.component;
            return std::unique_ptr<CubeWriter>(std::make_unique<SpectralExrWriter>(path, width, height, grid, o));
        },
        nullptr,  // the spectral EXR's line says float16 or float32 (RenderOutputs::commit)
    });
    t.push_back(CubeContainer{
        "hdf5", {"h5"}, "hdf5, hdf5:gzip[:1-9]", {"hdf5", "hdf5:gzip"}, ".h5",
        [](const std::string& entry, const std::string& options, const Where& at, std::string& out) {
            if (options.empty()) return out.clear(), true;
            if (options == "gzip") return out = "gzip:4", true;
            if (options.rfind("gzip:", 0) != 0) return false;
            const std::string level = options.substr(5);
            if (level.size() != 1 || level[0] < '1' || level[0] > '9')
                failInput(at, "'{}': the gzip level is '{}'; expected one digit 1 to 9", entry, level);
            out = options;
            return true;
        },
        [](const std::filesystem::path& path, int width, int height, const Grid& grid, const CubeWriteSettings& s) {
            Hdf5WriteOptions o;
            o.gzipLevel = s.options.empty() ? 0 : s.options.back() - '0';
            o.attributes = s.provenance;
            o.component = s.component;
            return std::unique_ptr<CubeWriter>(std::make_unique<Hdf5CubeWriter>(path, width, height, grid, o));
        },
        [](const std::filesystem::path&, const CubeWriteSettings& s, const std::string& cube) {
            return fmt::format("HDF5 /cube [rows, columns, bands], {}{}", cube,
                               s.options.empty() ? "" : fmt::format(", gzip {}", s.options.back()));
        },
    });
    t.push_back(CubeContainer{
        "arad", {"mat"}, "arad", {"arad"}, ".mat",
        [](const std::string&, const std::string& options, const Where&, std::string& out) {
            return out.clear(), options.empty();
        },
        [](const std::filesystem::path& path, int width, int height, const Grid& grid, const CubeWriteSettings& s) {
            return std::unique_ptr<CubeWriter>(std::make_unique<AradMatWriter>(path, width, height, grid, s.provenance));
        },
        [](const std::filesystem::path&, const CubeWriteSettings&, const std::string&) {
            return std::string("the ARAD layout, MATLAB v7.3: cube rows × columns × 31 (400–700 nm / 10 nm) / "
                               "norm_factor, bands");
        },
    });
    t.push_back(CubeContainer{
        "envi", {}, "envi[:bsq|bil|bip]", {"envi", "envi:bsq", "envi:bil", "envi:bip"}, ".hdr",
        [](const std::string&, const std::string& options, const Where&, std::string& out) {
            if (options.empty() || options == "bsq" || options == "bil" || options == "bip")
                return out = options.empty() ? "bsq" : options, true;
            return false;
        },
        [](const std::filesystem::path& path, int width, int height, const Grid& grid, const CubeWriteSettings& s) {
            EnviWriteOptions o;
            o.interleave = s.options == "bil" ? EnviInterleave::Bil : s.options == "bip" ? EnviInterleave::Bip : EnviInterleave::Bsq;
            // The writer says the grid and its rule itself (`metamer grid`, `metamer resampling`).
            for (const auto& a : s.provenance)
                if (a.first != "metamer:grid" && a.first != "metamer:resampling") o.attributes.push_back(a);
            o.component = s.component;
            return std::unique_ptr<CubeWriter>(std::make_unique<EnviCubeWriter>(path, width, height, grid, o));
        },
        [](const std::filesystem::path& path, const CubeWriteSettings& s, const std::string& cube) {
            return fmt::format("ENVI header + {} ({}), {}", path.stem().string() + ".img", s.options, cube);
        },
    });
    return t;
}

}  // namespace

const std::vector<CubeContainer>& cubeFormats() {
    static const std::vector<CubeContainer> table = makeTable();
    return table;
}

std::vector<ChosenCubeFormat> defaultCubeFormats() { return {ChosenCubeFormat{&cubeFormats().front(), ""}}; }

std::vector<ChosenCubeFormat> parseCubeFormats(const std::vector<std::string>& names, const Where& where) {
    const std::vector<CubeContainer>& table = cubeFormats();
    std::vector<std::string> formatNames, syntaxes, entries;
    for (const CubeContainer& f : table) {
        formatNames.push_back(f.name);
        syntaxes.push_back(f.syntax);
        entries.insert(entries.end(), f.entries.begin(), f.entries.end());
    }
    auto listed = [](const std::vector<std::string>& v) {  // "a, b or c"
        std::string s;
        for (size_t i = 0; i < v.size(); ++i) s += (i == 0 ? "" : i + 1 == v.size() ? " or " : ", ") + v[i];
        return s;
    };
    if (names.empty()) failInput(where, "no format named; expected {} (comma-separated)", listed(formatNames));
    std::vector<std::string> chosen(table.size());
    std::vector<bool> named(table.size(), false);
    for (size_t i = 0; i < names.size(); ++i) {
        const std::string& n = names[i];
        const Where at = where.key.rfind("--", 0) == 0 ? where : where.index(i);
        const size_t colon = n.find(':');
        const std::string head = n.substr(0, colon), options = colon == std::string::npos ? "" : n.substr(colon + 1);
        bool ok = false;
        for (size_t k = 0; k < table.size() && !ok; ++k) {
            const CubeContainer& f = table[k];
            if (head != f.name && std::find(f.aliases.begin(), f.aliases.end(), head) == f.aliases.end()) continue;
            std::string normalized;
            if ((ok = f.parse(n, options, at, normalized))) {
                chosen[k] = normalized;
                named[k] = true;
            }
        }
        if (!ok) {
            const std::string near = closestMatch(n, entries);
            failInput(at, "'{}' is not a cube format; expected {}{}", n, listed(syntaxes),
                      near.empty() ? "" : fmt::format(" (did you mean '{}'?)", near));
        }
    }
    std::vector<ChosenCubeFormat> out;
    for (size_t k = 0; k < table.size(); ++k)
        if (named[k]) out.push_back({&table[k], chosen[k]});
    return out;
}

}  // namespace metamer
