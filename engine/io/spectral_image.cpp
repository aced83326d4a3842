#include "io/spectral_image.h"

#include "core/error.h"
#include "core/file_reads.h"
#include "io/envi_cube.h"
#include "io/hdf5_cube.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>

namespace fs = std::filesystem;

namespace metamer {

namespace {

bool isRegularFile(const fs::path& path) {
    std::error_code ec;
    return fs::is_regular_file(fs::status(path, ec));
}

std::string lowerExtension(const fs::path& path) {
    std::string e = path.extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

}  // namespace

const char* cubeFormatName(CubeFormat format) {
    switch (format) {
        case CubeFormat::Exr: return "OpenEXR";
        case CubeFormat::Hdf5: return "HDF5";
        case CubeFormat::Envi: return "ENVI";
    }
    return "?";
}

std::optional<CubeFormat> cubeFormatOf(const fs::path& path) {
    try {
        // A FIFO or a device would block or never end: only regular files are opened.
        if (!isRegularFile(path)) return std::nullopt;
        unsigned char head[8] = {};
        std::ifstream in(path, std::ios::binary);
        in.read(reinterpret_cast<char*>(head), sizeof head);
        const std::streamsize got = in ? std::streamsize(sizeof head) : in.gcount();
        static const unsigned char kExr[4] = {0x76, 0x2f, 0x31, 0x01};
        if (got >= 4 && std::memcmp(head, kExr, 4) == 0) return CubeFormat::Exr;
        if (hasHdf5Signature(path)) return CubeFormat::Hdf5;  // also after a user block
        if (isEnviHeaderFile(path)) return CubeFormat::Envi;
        const std::string ext = lowerExtension(path);
        if (ext == ".img" || ext == ".raw" || ext == ".dat") {
            if (isEnviHeaderFile(fs::path(path).replace_extension(".hdr")) ||
                isEnviHeaderFile(fs::path(path.string() + ".hdr")))
                return CubeFormat::Envi;
        }
    } catch (const std::exception&) {
        // A path the file system cannot even look at (too long, bad encoding): not a cube.
    }
    return std::nullopt;
}

SpectralImage readSpectralImage(const fs::path& path, const CubeHeaderCheck& check) {
    const Where where{path.string()};
    requireRegularFile(path, where, "spectral image");
    const std::optional<CubeFormat> format = cubeFormatOf(path);
    if (!format)
        failInput(where, "not a spectral image: expected OpenEXR, HDF5 or ENVI (a header starting with 'ENVI', or a "
                         ".img, .raw or .dat beside one)");
    switch (*format) {
        case CubeFormat::Exr: return readSpectralExrImage(path, check);
        case CubeFormat::Hdf5: return readHdf5Cube(path, check);
        case CubeFormat::Envi: return readEnviCube(path, check);
    }
    failInput(where, "not a spectral image");
}

}  // namespace metamer
