#include "render/output_path.h"

#include "core/error.h"
#include "core/file_reads.h"

#include <algorithm>
#include <cctype>

namespace metamer {

namespace fs = std::filesystem;

namespace {

// ".exr, .h5, .hdr or .png": the extensions a named file may have, in the cube table's order.
std::vector<std::string> namedExtensions() {
    std::vector<std::string> all;
    for (const CubeContainer& c : cubeFormats()) all.push_back(c.extension);
    all.push_back(".png");
    return all;
}

std::string listed(const std::vector<std::string>& items, const std::string& prefix) {
    std::string text;
    for (size_t i = 0; i < items.size(); ++i)
        text += (i == 0 ? "" : i + 1 == items.size() ? " or " : ", ") + prefix + items[i];
    return text;
}

std::string lowerCase(std::string text) {
    for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return text;
}

// Files a user may mean by -o that Metamer does not write: a name ending in one of these is an error,
// not a folder (-o result.tiff made a folder result.tiff/ once). Raster images, camera raws and the
// other cube containers; a hint where Metamer writes the like under another name. Lower case,
// matched in any case. ".dat" is left out: ENVI data use it, but so do too many folders.
struct RefusedExtension {
    const char* extension;
    const char* hint;
};
constexpr RefusedExtension kRefused[] = {
    {".tif", ""}, {".tiff", ""}, {".jpg", ""}, {".jpeg", ""}, {".jp2", ""}, {".j2k", ""}, {".jxl", ""},
    {".webp", ""}, {".avif", ""}, {".heic", ""}, {".heif", ""}, {".gif", ""}, {".bmp", ""}, {".tga", ""},
    {".ppm", ""}, {".pgm", ""}, {".pbm", ""}, {".pnm", ""}, {".pfm", ""}, {".dpx", ""}, {".cin", ""},
    {".psd", ""}, {".raw", ""},
    {".dng", "--sensor writes a DNG beside the cube, named after it"},
    {".hdf5", "HDF5 cubes are NAME.h5"}, {".he5", "HDF5 cubes are NAME.h5"}, {".hdf", "HDF5 cubes are NAME.h5"},
    {".img", "an ENVI cube is named by its header, NAME.hdr (NAME.img holds its data)"},
    {".bsq", "an ENVI cube is named by its header, NAME.hdr, its layout chosen with --format envi:bsq"},
    {".bil", "an ENVI cube is named by its header, NAME.hdr, its layout chosen with --format envi:bil"},
    {".bip", "an ENVI cube is named by its header, NAME.hdr, its layout chosen with --format envi:bip"},
    {".nc", ""}, {".fits", ""}, {".fit", ""}, {".fts", ""}, {".npy", ""}, {".npz", ""}, {".zarr", ""},
};

const RefusedExtension* refused(const std::string& lowerExtension) {
    for (const RefusedExtension& r : kRefused)
        if (lowerExtension == r.extension) return &r;
    return nullptr;
}

}  // namespace

std::vector<std::string> refusedOutputExtensions() {
    std::vector<std::string> all;
    for (const RefusedExtension& r : kRefused) all.push_back(r.extension);
    return all;
}

const CubeContainer* namedCubeFormat(const std::string& extension) {
    if (extension.empty()) return nullptr;
    for (const CubeContainer& c : cubeFormats())
        if (c.extension == extension) return &c;
    return nullptr;
}

OutputPath parseOutputPath(const std::string& text, const std::string& flag) {
    const Where where{"", flag};
    if (text.empty()) failInput(where, "expected a folder or an output file's name, got an empty string");
    const fs::path path(text);
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    const std::string files = listed(namedExtensions(), "NAME");
    const std::string expected = fmt::format("expected a folder or an output file named {}", files);
    // A folder: said so with a trailing '/', or one that exists.
    if (text.back() == '/' || fs::is_directory(st)) {
        // stat("file/") fails with ENOTDIR: look at the name without its slashes.
        const size_t end = text.find_last_not_of('/');
        const fs::file_status named = end == std::string::npos ? st : fs::status(text.substr(0, end + 1), ec);
        if (fs::exists(named) && !fs::is_directory(named))
            failInput(where, "'{}' is {}, not a folder; {}", text,
                      fs::is_regular_file(named) ? "a file" : specialFileKind(named), expected);
        return {path, "", ""};
    }
    const std::string extension = path.extension().string();
    const std::vector<std::string> known = namedExtensions();
    const bool namesAFile = std::find(known.begin(), known.end(), extension) != known.end();
    // Something that exists is replaced only when it is a file with an output's name.
    if (fs::exists(st) && !(namesAFile && fs::is_regular_file(st)))
        failInput(where, "'{}' is {}, not a folder; {}", text, fs::is_regular_file(st) ? "a file" : specialFileKind(st),
                  expected);
    const std::string lower = lowerCase(extension);
    const std::string orFolder = fmt::format("(for a folder named '{}', write '{}/')", text, text);
    // X.EXR: the outputs are written with the table's lower-case extensions, so X.EXR would name a
    // file the run does not write (X.exr); a folder of that name would surprise as much.
    if (!namesAFile && std::find(known.begin(), known.end(), lower) != known.end())
        failInput(where, "'{}': output files are named in lower case; write '{}' {}", text,
                  (path.parent_path() / (path.stem().string() + lower)).string(), orFolder);
    if (const RefusedExtension* r = refused(lower))
        failInput(where, "'{}' names a {} file{}; Metamer writes {} {}", text, extension,
                  *r->hint ? fmt::format(": {}", r->hint) : ", which Metamer does not write", files, orFolder);
    // Any other name is a folder, dots and all: runs/v1.2, 2026.12.05.
    if (!namesAFile) return {path, "", ""};
    const fs::path folder = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    const fs::file_status folderStatus = fs::status(folder, ec);
    if (fs::exists(folderStatus) && !fs::is_directory(folderStatus))
        failInput(where, "'{}': its folder '{}' is {}, not a folder", text, folder.string(),
                  fs::is_regular_file(folderStatus) ? "a file" : specialFileKind(folderStatus));
    return {folder, path.stem().string(), extension};
}

void requireNamedOutput(const fs::path& file, bool writesCube, bool writesPng, const std::vector<ChosenCubeFormat>& formats,
                        const std::string& formatsFrom) {
    const Where where{"", "--out"};
    const std::string extension = file.extension().string();
    if (extension == ".png") {
        if (!writesPng)
            failInput(where, "'{}' names the display PNG, which this run does not write (--no-png, or --write "
                      "without png, or a detector with no display image); name the cube instead", file.string());
        return;
    }
    const CubeContainer* named = namedCubeFormat(extension);
    if (!named) failInput(where, "'{}' is not the name of an output", file.string());
    if (!writesCube)
        failInput(where, "'{}' names the spectral cube, which this run does not write (--write without cube); "
                  "name the PNG, or add cube to --write", file.string());
    for (const ChosenCubeFormat& f : formats)
        if (f.format == named) return;
    std::vector<std::string> chosen;
    for (const ChosenCubeFormat& f : formats) chosen.push_back(f.format->name);
    failInput(where, "'{}' names a cube in {} format, but {} asks for {}; name the file {}, or add {} to {}", file.string(),
              named->name, formatsFrom.empty() ? "the run" : formatsFrom, listed(chosen, ""),
              formats.empty() ? "" : file.stem().string() + formats.front().format->extension, named->name,
              formatsFrom.empty() ? "--format" : formatsFrom);
}

}  // namespace metamer
