// Hyperspectral cubes as ENVI files: a text header <stem>.hdr ("key = value" lines, {…} lists)
// beside the raw samples <stem>.img, float32 in the host's byte order, band-sequential (bsq),
// band-interleaved by line (bil) or by pixel (bip). What ENVI, Spectral Python, GDAL and most
// remote-sensing tools read. Written by hand: the format is small, and the header parser is a
// fuzz target (fuzz/envi_header_fuzzer.cpp). See docs/io.md. Tests: engine/io/envi_cube_test.cpp.
#pragma once

#include "io/cube_writer.h"
#include "core/error.h"
#include "io/exr_file.h"
#include "io/spectral_exr.h"

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace metamer {

class AtomicOutput;

enum class EnviInterleave {
    Bsq,  // band-sequential: [band][line][sample]
    Bil,  // band-interleaved by line: [line][band][sample]
    Bip,  // band-interleaved by pixel: [line][sample][band], the cube's own order
};
const char* enviInterleaveName(EnviInterleave interleave);  // "bsq", "bil", "bip"

struct EnviWriteOptions {
    EnviInterleave interleave = EnviInterleave::Bsq;
    StringAttributes attributes;  // header lines "metamer <name> = <value>" ("metamer:" dropped from names)
    SpectralComponent component = SpectralComponent::Emissive;  // radiance or reflectance
};

// Writes a cube strip by strip (rows in order): <stem>.hdr is `headerPath`, the samples go to
// <stem>.img. Memory stays bounded: bsq pre-sizes the data file and writes each band's rows at
// their offset. Both files appear only at commit(), the data first, so a header means complete
// data; a writer destroyed before that leaves neither (AtomicOutput). Header: samples, lines,
// bands, header offset, file type, data type 4, interleave, byte order, wavelength units,
// wavelength, fwhm, band names, default bands (nearest 610, 550, 465 nm), description, metamer
// quantity, metamer units, metamer grid, metamer resampling, and options.attributes. Runtime errors
// name the path; a header name not ending in .hdr is an input error.
class EnviCubeWriter : public CubeWriter {
public:
    EnviCubeWriter(const std::filesystem::path& headerPath, int width, int height, const Grid& grid,
                   const EnviWriteOptions& options = {});
    ~EnviCubeWriter() override;
    EnviCubeWriter(const EnviCubeWriter&) = delete;
    EnviCubeWriter& operator=(const EnviCubeWriter&) = delete;
    // `rows` rows starting at `firstRow`, pixel-interleaved (width × rows × bands floats).
    void writeRows(int firstRow, int rows, const float* data) override;
    // Completes the temporary files (data and header) and returns them, the data first for commitTogether (io/atomic_file.h),
    // which renames a run's files into place together; commit() is finish() and that.
    std::vector<AtomicOutput*> finish() override;
    void commit();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// The whole cube through EnviCubeWriter.
void writeEnviCube(const std::filesystem::path& headerPath, const SpectralCube& cube,
                   const EnviWriteOptions& options = {});

// Whether the file starts with "ENVI", as every ENVI header does.
bool isEnviHeaderFile(const std::filesystem::path& path);

// <stem>.img for <stem>.hdr.
std::filesystem::path enviDataPathFor(const std::filesystem::path& headerPath);

// A parsed header of a spectral cube.
struct EnviHeader {
    int samples = 0, lines = 0, bands = 0;
    size_t headerOffset = 0;  // bytes before the first sample in the data file
    int dataType = 4;         // 4: float32, 5: float64
    EnviInterleave interleave = EnviInterleave::Bsq;
    int byteOrder = 0;                     // 0: little-endian, 1: big-endian
    std::vector<double> wavelengths_nm;    // one per band, converted to nm
    std::vector<double> fwhm_nm;           // one per band, or empty when the header has none
    std::string wavelengthUnits;           // as written ("Nanometers", "um", …)
    // Every "key = value" in order: keys in lower case with single spaces, values trimmed, a {…}
    // value without its braces.
    std::vector<std::pair<std::string, std::string>> fields;

    // The value of the last field named `key` (lower case), or nothing.
    std::optional<std::string> field(std::string_view key) const;
    size_t bytesPerValue() const { return dataType == 5 ? 8 : 4; }
};

// Parses the text of a .hdr: "ENVI" on the first non-empty line, then "key = value" lines (";"
// starts a comment line; a {…} value may span lines; keys are case-insensitive). Required:
// samples, lines (1 to 65536), bands (1 to 10000), data type (4 or 5), interleave, byte order
// (0 or 1: readers disagree on a default), wavelength (one per band, finite) and wavelength units
// (Nanometers or Micrometers); header offset defaults to 0, fwhm is optional. Input errors name
// `where`'s file, the key and, for a syntax error, the line. Never anything but metamer::Error on
// any bytes: headers over 16 MiB and NUL bytes are refused before parsing.
EnviHeader parseEnviHeader(const std::string& text, const Where& where);

// Reads a cube from its .hdr or its data file (the sibling is found: <stem>.hdr or <stem>.img.hdr
// for a data file; <stem>.img, <stem>, .dat, .raw, .bsq, .bil, .bip for a header). The data file
// must hold exactly header offset + samples·lines·bands values. "metamer quantity = reflectance"
// marks reflectance; "metamer grid" gives the exact grid when it agrees with the wavelengths,
// which must be uniform within 1e-4 nm. Input errors name the file (header or data) and the key.
SpectralImage readEnviCube(const std::filesystem::path& path, const CubeHeaderCheck& check = {});

}  // namespace metamer
