// Spectral OpenEXR files in the layout of Fichet, Pacanowski and Wilkie, "An OpenEXR Layout for
// Spectral Images", JCGT 10(3), 2021: one channel per band, named S0.<λ>nm (emissive) or
// T.<λ>nm (reflective), with a comma as the decimal separator. See docs/io.md.
#pragma once

#include "io/cube_writer.h"
#include "io/exr_file.h"
#include "spectral/bispectral.h"
#include "spectral/cube.h"

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

class AtomicOutput;

enum class SpectralComponent {
    Emissive,    // S0.<λ>nm: spectral radiance
    Reflective,  // T.<λ>nm: reflectance
};

struct ExrWriteOptions {
    bool half = false;               // float16 instead of float32
    std::string compression = "piz"; // an OpenEXR compression (io/exr_file.h): none, rle, zips, zip, piz, ...
    std::vector<std::pair<std::string, std::string>> extraAttributes;  // string header attributes
    // R, G, B, A preview channels beside the bands, so that ordinary viewers show an image rather
    // than the first three bands, with the chromaticities of R, G, B (docs/io.md, "Preview
    // channels"). Absent: the bands alone.
    std::optional<ExrChromaticities> preview;
    // Emissive: S0.<λ>nm channels of spectral radiance; reflective: T.<λ>nm channels of a
    // reflectance factor (the ground truth's reflectance map), read back as a reflective cube.
    SpectralComponent component = SpectralComponent::Emissive;
};

// The preview's channel names, in the order its pixels are interleaved.
const std::vector<std::string>& previewChannelNames();  // {"R", "G", "B", "A"}

struct ExrWriteReport {
    size_t clampedToHalfMax = 0;  // half only: finite values beyond ±65504 written as ±65504
    size_t nonFinite = 0;         // NaN or ±Inf values, written unchanged
};

// Channel name of an emissive band: 552.5 -> "S0.552,500000nm"; of a reflective one, "T.552,500000nm".
std::string spectralChannelName(double wavelength_nm, SpectralComponent component = SpectralComponent::Emissive);

// Writes the cube as emissive spectral radiance (S0 channels) through AtomicOutput, so the file
// appears complete or not at all. Header: spectralLayoutVersion, emissiveUnits, metamer:grid,
// metamer:quantity, plus options.extraAttributes. Throws a runtime error naming the path.
ExrWriteReport writeSpectralExr(const std::filesystem::path& path, const SpectralCube& cube,
                                const ExrWriteOptions& options = {});

// Writes a cube strip by strip (rows in order), for images larger than memory. The file appears
// only at commit(); a writer destroyed before that leaves nothing behind (AtomicOutput).
class SpectralExrWriter : public CubeWriter {
public:
    SpectralExrWriter(const std::filesystem::path& path, int width, int height, const Grid& grid,
                      const ExrWriteOptions& options = {});
    ~SpectralExrWriter() override;
    SpectralExrWriter(const SpectralExrWriter&) = delete;
    SpectralExrWriter& operator=(const SpectralExrWriter&) = delete;
    // `rows` rows starting at `firstRow`, pixel-interleaved (width × rows × bands floats); with a
    // preview, its rows too (width × rows × 4 floats: R, G, B, A), else a runtime error.
    void writeRows(int firstRow, int rows, const float* data) override;
    void writeRows(int firstRow, int rows, const float* data, const float* preview) override;
    // Completes the temporary file and returns it for commitTogether (io/atomic_file.h),
    // which renames a run's files into place together; commit() is finish() and that.
    std::vector<AtomicOutput*> finish() override;
    const ExrWriteReport& report() const;
    size_t clampedValues() const override { return report().clampedToHalfMax; }
    ExrWriteReport commit();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

struct SpectralExrImage {
    SpectralCube cube;
    SpectralComponent component = SpectralComponent::Emissive;
};
// What every cube reader returns (io/spectral_image.h: EXR, HDF5, ENVI).
using SpectralImage = SpectralExrImage;

// Called by every cube reader with the cube's size from its header, before the data are read;
// throws to refuse it (a texture too large for the grid). The readers then refuse, themselves,
// a cube whose values would take more than a quarter of the machine's memory.
using CubeHeaderCheck = std::function<void(int width, int height, int bands)>;

// The Grid of a cube's band centres, increasing: they must be uniform within 1e-4 nm. `gridText`
// ("300:740:5", as the writers record it) gives the exact values when it agrees with them; one
// band gets a step of 1 nm unless `gridText` says otherwise. Not checked against the render limits
// of Grid::validate. Errors name `where` and say which two of `what` ("bands") are off.
Grid gridOfWavelengths(const std::vector<double>& wavelengths_nm, const std::string& gridText, const Where& where,
                       const std::string& what = "spectral channels");

// Whether an image with these channel names is in the spectral layout (any `S0.` or `T.`
// channel), so that readSpectralExrImage, not a plain image reader, should read it.
bool hasSpectralChannels(const std::vector<std::string>& channelNames);

// Reads the S0 channels (or, if there are none, the T channels) into a cube, bands sorted by
// wavelength. Other channels (R, G, B, S1..S3, bispectral T.<λ>nm.<λ>nm) are ignored. The
// wavelengths must form a uniform grid within 1e-4 nm; the Grid is taken from them (not checked
// against the render limits of Grid::validate). Input errors name the file.
SpectralExrImage readSpectralExrImage(const std::filesystem::path& path, const CubeHeaderCheck& check = {});

// The same, for callers that only take emissive data: a file with only T channels is an error.
SpectralCube readSpectralExr(const std::filesystem::path& path);

// A Donaldson matrix stored as a bispectral image in the same layout: a 1×1 image whose channels
// T.<λin><unit>.<λout><unit> hold D(λin, λout) in nm⁻¹ (docs/scene-format.md, "Donaldson matrix
// files"). The two axes are the distinct wavelengths named; a pair with no channel is 0. Reflective
// T.<λ>nm channels (the diagonal's reflectance) and any other channel are not part of D: they are
// counted, for the caller to warn about, and ignored. Input errors name the file and, for a bad
// value, the channel.
struct BispectralExr {
    BispectralMatrix matrix;
    size_t reflectiveChannels = 0;  // T.<λ>nm: reflectance, which belongs in the material's diffuse
    size_t otherChannels = 0;       // R, G, B, S0..S3, ...
};
BispectralExr readBispectralExr(const std::filesystem::path& path);

}  // namespace metamer
