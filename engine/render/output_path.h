// What `metamer render -o PATH` means: a folder the outputs go into under the scene's name, or one
// output file whose name gives every output its stem (-o result.exr: result.exr and result.png).
// An existing folder or a path ending in '/' is a folder. Otherwise NAME.exr, NAME.h5, NAME.mat or NAME.hdr
// (the cube formats' extensions, render/cube_formats.h) or NAME.png (the display image) is a file;
// a name ending in the extension of an image or cube Metamer does not write (.tiff, .jpg, .hdf5,
// .img, ...: refusedOutputExtensions, in any case) or in an output's extension in another case
// (X.EXR) is an input error naming the flag and the files Metamer writes; any other name is a
// folder, created if missing: `out`, `runs/v1.2`, `2026.12.05`.
// docs/cli.md, "Output names". Tests: engine/render/output_path_test.cpp, tests/cli_test.cpp (CliOutputName.*).
#pragma once

#include "render/cube_formats.h"

#include <filesystem>
#include <string>
#include <vector>

namespace metamer {

struct OutputPath {
    std::filesystem::path folder;
    std::string stem;       // the named file's stem; empty: the scene's
    std::string extension;  // the named file's (".exr", ".h5", ".mat", ".hdr", ".png"); empty: a folder
};

// Reads `text`, the value of `flag` (for errors), as above. A path that exists is checked now: a
// folder where a file is named, or a file or a device where a folder is, is an input error.
OutputPath parseOutputPath(const std::string& text, const std::string& flag);

// The extensions -o refuses (lower case, ".tiff"), in the order docs/cli.md lists them.
std::vector<std::string> refusedOutputExtensions();

// The cube format whose file has `extension` (".h5": hdf5), or null (".png", "").
const CubeContainer* namedCubeFormat(const std::string& extension);

// That the run writes `file`, the file -o named: a cube extension needs the cube among the outputs
// and its format among `formats` (`formatsFrom` says who chose them: "--format", "the scene's
// output.format" or "" for -o itself), .png needs the display PNG. An input error naming --out and
// what to change otherwise.
void requireNamedOutput(const std::filesystem::path& file, bool writesCube, bool writesPng,
                        const std::vector<ChosenCubeFormat>& formats, const std::string& formatsFrom);

}  // namespace metamer
