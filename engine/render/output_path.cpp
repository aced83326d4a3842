#include "render/output_path.h"

#include "core/error.h"
#include "core/file_reads.h"

#include <algorithm>

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

}  // namespace

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
    const std::string expected = fmt::format(
        "expected a folder (an existing one, a path ending in '/', or a name without an extension) or an output "
        "file named {}", listed(namedExtensions(), "NAME"));
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
    if (extension.empty()) return {path, "", ""};
    if (!namesAFile)
        failInput(where, "'{}' is ambiguous: '{}' is not the extension of an output; {} (for a folder named '{}', "
                  "write '{}/')", text, extension, expected, text, text);
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
