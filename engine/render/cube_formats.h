// The containers a spectral cube can be written in, as one table: its name in --format and the
// scene's output.format, its options, its file name and the writer that makes it (every writer
// is a CubeWriter, io/cube_writer.h). A new container is its writer's two files in io/ and one
// row in cube_formats.cpp. docs/io.md. Tests: tests/cli_test.cpp (CliOutputs), tests/bad_inputs_test.cpp.
#pragma once

#include "core/error.h"
#include "io/cube_writer.h"
#include "io/exr_file.h"
#include "io/spectral_exr.h"
#include "spectral/grid.h"

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

using Attributes = std::vector<std::pair<std::string, std::string>>;

// What a writer is opened with: the row's options as parsed ("gzip:4", "bil", ""), what every file
// of the render carries, and the OpenEXR flags (--half, --compression).
struct CubeWriteSettings {
    std::string options;
    Attributes provenance;
    bool half = false;
    std::string compression = "piz";
    // The display preview's primaries, when the render writes a display image: OpenEXR then
    // carries R, G, B, A beside the bands (io/spectral_exr.h); the other containers hold bands only.
    std::optional<ExrChromaticities> preview;
    SpectralComponent component = SpectralComponent::Emissive;  // radiance (and illumination), or reflectance
};

struct CubeContainer {
    std::string name;                  // "exr", "hdf5", "envi": what --format names
    std::vector<std::string> aliases;  // other names for it ("h5")
    std::string syntax;                // for messages: "hdf5, hdf5:gzip[:1-9]"
    std::vector<std::string> entries;  // every complete entry it accepts, for suggestions
    std::string extension;             // the file's (ENVI: the header's; its data is <stem>.img)
    // The options after "name:" ("" without), checked and normalized; false when they are not
    // this format's (the caller says so); input errors of their own name `at`.
    std::function<bool(const std::string& entry, const std::string& options, const Where& at, std::string& normalized)>
        parse;
    std::function<std::unique_ptr<CubeWriter>(const std::filesystem::path& path, int width, int height, const Grid& grid,
                                              const CubeWriteSettings& settings)>
        open;
    // One line for the run's report: the file's layout; `cube` says the size, grid and units.
    std::function<std::string(const std::filesystem::path& path, const CubeWriteSettings& settings, const std::string& cube)>
        describe;
};

// The table, in the order the files are written and reported.
const std::vector<CubeContainer>& cubeFormats();

struct ChosenCubeFormat {
    const CubeContainer* format = nullptr;
    std::string options;  // normalized
};

// The default: OpenEXR.
std::vector<ChosenCubeFormat> defaultCubeFormats();
// "exr", "hdf5", "hdf5:gzip" (level 4), "hdf5:gzip:N" (1-9), "envi" (BSQ), "envi:bsq|bil|bip";
// at least one; a format named twice takes the last entry's options. In the table's order. Input
// errors name `where` and the entry.
std::vector<ChosenCubeFormat> parseCubeFormats(const std::vector<std::string>& names, const Where& where);

}  // namespace metamer
