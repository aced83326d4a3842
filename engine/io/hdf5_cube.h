// Hyperspectral cubes as HDF5 files (libhdf5), the layout h5py, MATLAB and most remote-sensing
// tools read without a plugin (and the ARAD challenge's MATLAB v7.3 layout, AradMatWriter below): dataset /cube float32 [rows, columns, bands] (chunked one row at a
// time, optionally gzip with shuffle), /wavelength_nm and /fwhm_nm float64 [bands], and string
// attributes saying what the numbers are. See docs/io.md. Tests: engine/io/hdf5_cube_test.cpp,
// tests/python/test_arad.py (h5py and mat73 read the ARAD layout).
#pragma once

#include "io/cube_writer.h"
#include "io/exr_file.h"
#include "io/spectral_exr.h"

#include <filesystem>
#include <memory>

namespace metamer {

class AtomicOutput;

struct Hdf5WriteOptions {
    int gzipLevel = 0;            // 0: no compression; 1-9: deflate (with the shuffle filter)
    StringAttributes attributes;  // UTF-8 string attributes on the root group "/"
    SpectralComponent component = SpectralComponent::Emissive;  // radiance or reflectance
};

// Writes a cube strip by strip (rows in order) into one HDF5 file, each strip one hyperslab, so
// memory stays bounded whatever the image size. The file appears only at commit(); a writer
// destroyed before that leaves nothing behind (AtomicOutput). Layout:
//   /cube           float32 [rows, columns, bands], chunks [1, min(columns, 1024), bands],
//                   dimensions labelled y, x, wavelength with the scales below attached
//                   attributes units ("W sr-1 m-2 nm-1", UDUNITS, or "1"), units_readable
//                   ("W·sr⁻¹·m⁻²·nm⁻¹"), quantity ("spectral radiance" or "reflectance"), grid
//                   (Grid::str()), band_width_nm, resampling, interleave
//   /wavelength_nm  float64 [bands], the band centres
//   /fwhm_nm        float64 [bands], the band widths (the grid step)
//   /wavelength     float64 [bands], the band centres again: the dimension scale `wavelength`
//   /y, /x          int32 row and column indices: the dimension scales `y` and `x`
// so that netCDF readers (xarray with h5netcdf) see dimensions y, x, wavelength and a wavelength
// coordinate in nm.
// HDF5 failures are runtime errors naming the path.
class Hdf5CubeWriter : public CubeWriter {
public:
    Hdf5CubeWriter(const std::filesystem::path& path, int width, int height, const Grid& grid,
                   const Hdf5WriteOptions& options = {});
    ~Hdf5CubeWriter() override;
    Hdf5CubeWriter(const Hdf5CubeWriter&) = delete;
    Hdf5CubeWriter& operator=(const Hdf5CubeWriter&) = delete;
    // `rows` rows starting at `firstRow`, pixel-interleaved (width × rows × bands floats).
    void writeRows(int firstRow, int rows, const float* data) override;
    // Completes the temporary file and returns it for commitTogether (io/atomic_file.h),
    // which renames a run's files into place together; commit() is finish() and that.
    std::vector<AtomicOutput*> finish() override;
    void commit();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// The ARAD / NTIRE spectral-reconstruction layout (issue 49, item 4; docs/io.md, "ARAD layout"): a
// MATLAB v7.3 MAT-file (an HDF5 file behind a 512-byte MATLAB header) holding
//   cube         single, rows × columns × 31 in MATLAB (HDF5 [31, columns, rows]): the render's
//                bands put onto 400, 410, …, 700 nm by the engine's one rule (spectral/resampling.h:
//                the render's own band where its grid has that centre, else the mean over the 10 nm
//                band or the interpolant), divided by norm_factor so the largest is 1
//   bands        double, 1 × 31: the band centres in nm
//   norm_factor  double, 1 × 1: the divisor — cube·norm_factor is spectral radiance, W·sr⁻¹·m⁻²·nm⁻¹
// each with its MATLAB_class attribute, so MATLAB's load, h5py and the mat73 package read it. The
// bands need the whole image (the divisor is its maximum): rows are held until finish(), 31 floats
// a pixel. The render's grid must cover 400–700 nm (an input error naming --format otherwise).
class AradMatWriter : public CubeWriter {
public:
    AradMatWriter(const std::filesystem::path& path, int width, int height, const Grid& grid,
                  const StringAttributes& attributes = {});
    ~AradMatWriter() override;
    void writeRows(int firstRow, int rows, const float* data) override;
    std::vector<AtomicOutput*> finish() override;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// The whole cube through Hdf5CubeWriter.
void writeHdf5Cube(const std::filesystem::path& path, const SpectralCube& cube, const Hdf5WriteOptions& options = {});

// Reads /cube (rank 3, any floating-point type, converted to float32) and /wavelength_nm
// (increasing, uniform within 1e-4 nm; the Grid is taken from them, exact when the cube's `grid`
// attribute agrees). The `quantity` attribute says reflectance or radiance (absent: radiance).
// Input errors name the file and the dataset or attribute ("/cube", "/wavelength_nm",
// "/cube.quantity"): not HDF5, truncated, missing, wrong rank or type, sizes that disagree, more
// than 2^34 values. The file must be a regular file (requireRegularFile), and HDF5 reads no other
// file on its behalf: an external or soft link, external storage or a virtual dataset for /cube or
// /wavelength_nm is an input error naming what was found (docs/io.md, "Reading cubes").
SpectralImage readHdf5Cube(const std::filesystem::path& path, const CubeHeaderCheck& check = {});

// That `path` is a regular file with the HDF5 signature where HDF5 looks for it: at offset 0, or
// after a user block at 512, 1024, 2048, ...
bool hasHdf5Signature(const std::filesystem::path& path);

}  // namespace metamer
