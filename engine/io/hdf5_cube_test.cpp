#include "io/hdf5_cube.h"

#include "io/atomic_file.h"
#include "io/spectral_image.h"

#include "support/cubes.h"
#include "support/temp_folder.h"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <hdf5_hl.h>

#include <cmath>
#include <chrono>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <poll.h>
#include <signal.h>
#include <thread>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace metamer;
namespace fs = std::filesystem;
using test::expectBitExact;
using test::randomCube;
using test::expectInputError;

namespace {

// A fresh folder per test; the hand-made files' HDF5 calls print nothing.
class Hdf5Cube : public test::TempFolderTest {
protected:
    void SetUp() override {
        TempFolderTest::SetUp();
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    }
};

// Writes the cube through the strip writer in strips of the given heights.
void writeInStrips(const fs::path& file, const SpectralCube& cube, const std::vector<int>& strips,
                   const Hdf5WriteOptions& options) {
    Hdf5CubeWriter writer(file, cube.width, cube.height, cube.grid, options);
    int row = 0;
    for (int rows : strips) {
        writer.writeRows(row, rows, cube.pixel(0, row));
        row += rows;
    }
    ASSERT_EQ(row, cube.height);
    writer.commit();
}

// --- Hand-made HDF5 files, for layouts our writer never makes ---------------------------------

hid_t create(const fs::path& file) { return H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT); }

void dataset(hid_t file, const char* name, hid_t type, const std::vector<hsize_t>& dims, hid_t memType,
             const void* values, bool chunked = false) {
    hid_t space = H5Screate_simple(int(dims.size()), dims.data(), nullptr);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    if (chunked) {
        std::vector<hsize_t> chunk(dims.size(), 1);
        H5Pset_chunk(dcpl, int(chunk.size()), chunk.data());
    }
    hid_t set = H5Dcreate2(file, name, type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    ASSERT_GE(set, 0) << name;
    if (values) ASSERT_GE(H5Dwrite(set, memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, values), 0);
    H5Dclose(set);
    H5Pclose(dcpl);
    H5Sclose(space);
}

void stringAttribute(hid_t object, const char* name, const char* value) {
    hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, H5T_VARIABLE);
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t a = H5Acreate2(object, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, type, &value);
    H5Aclose(a);
    H5Sclose(space);
    H5Tclose(type);
}

// A file with /cube float32 [rows, cols, bands] (zeros) and /wavelength_nm as given.
void writeForeign(const fs::path& path, std::vector<hsize_t> cubeDims, const std::vector<double>* wavelengths,
                  const char* quantity = nullptr) {
    hid_t f = create(path);
    size_t n = 1;
    for (hsize_t d : cubeDims) n *= d;
    std::vector<float> zeros(n, 0.0f);
    dataset(f, "cube", H5T_IEEE_F32LE, cubeDims, H5T_NATIVE_FLOAT, zeros.data());
    if (quantity) {
        hid_t cube = H5Dopen2(f, "cube", H5P_DEFAULT);
        stringAttribute(cube, "quantity", quantity);
        H5Dclose(cube);
    }
    if (wavelengths)
        dataset(f, "wavelength_nm", H5T_IEEE_F64LE, {wavelengths->size()}, H5T_NATIVE_DOUBLE, wavelengths->data());
    H5Fclose(f);
}

std::string readStringAttribute(hid_t object, const char* name) {
    hid_t a = H5Aopen(object, name, H5P_DEFAULT);
    if (a < 0) return "<missing>";
    hid_t type = H5Aget_type(a);
    std::string value = "<not a variable-length UTF-8 string>";
    if (H5Tis_variable_str(type) > 0 && H5Tget_cset(type) == H5T_CSET_UTF8) {
        char* text = nullptr;
        H5Aread(a, type, &text);
        value = text;
        H5free_memory(text);
    }
    H5Tclose(type);
    H5Aclose(a);
    return value;
}

// A cube file whose /cube is made by `makeCube(file, dims)` (values unwritten) beside a plain
// /wavelength_nm; `userBlock` bytes before HDF5's superblock (0: none).
void writeWith(const fs::path& path, const std::function<void(hid_t, const std::vector<hsize_t>&)>& makeCube,
               hsize_t userBlock = 0) {
    hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
    if (userBlock) H5Pset_userblock(fcpl, userBlock);
    hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
    ASSERT_GE(f, 0) << path;
    makeCube(f, {2, 2, 3});
    const std::vector<double> three = {400, 410, 420};
    dataset(f, "wavelength_nm", H5T_IEEE_F64LE, {3}, H5T_NATIVE_DOUBLE, three.data());
    H5Fclose(f);
    H5Pclose(fcpl);
}

// /cube with its values in an external raw file (HDF5 opens it only when the values are read).
void externalCube(hid_t f, const std::vector<hsize_t>& dims, const fs::path& raw) {
    hid_t space = H5Screate_simple(int(dims.size()), dims.data(), nullptr);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    ASSERT_GE(H5Pset_external(dcpl, raw.c_str(), 0, 12 * sizeof(float)), 0);
    hid_t set = H5Dcreate2(f, "cube", H5T_IEEE_F32LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    ASSERT_GE(set, 0);
    H5Dclose(set);
    H5Pclose(dcpl);
    H5Sclose(space);
}

// /cube as a virtual dataset mapping /data of `source` (which need not exist).
void virtualCube(hid_t f, const std::vector<hsize_t>& dims, const fs::path& source) {
    hid_t space = H5Screate_simple(int(dims.size()), dims.data(), nullptr);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    ASSERT_GE(H5Pset_virtual(dcpl, space, source.c_str(), "/data", space), 0);
    hid_t set = H5Dcreate2(f, "cube", H5T_IEEE_F32LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    ASSERT_GE(set, 0);
    H5Dclose(set);
    H5Pclose(dcpl);
    H5Sclose(space);
}

// readHdf5Cube in a child process, killed after `seconds`: a reader that opens a FIFO fails the
// test instead of hanging it. The error's "file: key: message" text, or "TIMEOUT", or "READ".
std::string readInChild(const fs::path& file, int seconds = 20) {
    int fds[2];
    if (::pipe(fds) != 0) return "PIPE";
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::close(fds[0]);
        std::string text = "READ";
        try {
            readHdf5Cube(file);
        } catch (const Error& e) {
            text = e.code() == ExitCode::BadInput ? e.text() : "NOT AN INPUT ERROR: " + e.text();
        }
        (void)!::write(fds[1], text.data(), text.size());
        ::_exit(0);
    }
    ::close(fds[1]);
    std::string text;
    pollfd p{fds[0], POLLIN, 0};
    char buffer[4096];
    bool ended = false;  // the child closed its end: it has finished
    while (!ended && ::poll(&p, 1, seconds * 1000) > 0) {
        const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
        if (n > 0) text.append(buffer, size_t(n));
        ended = n <= 0;
    }
    ::close(fds[0]);
    if (!ended) {
        ::kill(pid, SIGKILL);
        text = "TIMEOUT";
    }
    ::waitpid(pid, nullptr, 0);
    return text;
}

}  // namespace

TEST_F(Hdf5Cube, EmissiveRoundTripInUnevenStripsIsBitExact) {
    const SpectralCube cube = randomCube(7, 5, Grid{400, 520, 10}, 1);
    ASSERT_EQ(cube.bands(), 13);
    for (int gzip : {0, 1, 6, 9}) {
        const fs::path file = dir / fmt::format("cube-{}.h5", gzip);
        writeInStrips(file, cube, {2, 1, 2}, {.gzipLevel = gzip});
        const SpectralImage back = readHdf5Cube(file);
        EXPECT_EQ(back.component, SpectralComponent::Emissive);
        expectBitExact(cube, back.cube);
    }
    EXPECT_EQ(namesIn(), (std::vector<std::string>{"cube-0.h5", "cube-1.h5", "cube-6.h5", "cube-9.h5"}));
}

TEST_F(Hdf5Cube, ReflectiveRoundTripAndOneStripPerRow) {
    const SpectralCube cube = randomCube(3, 4, Grid{380, 780, 20}, 2);
    const fs::path file = dir / "reflectance.h5";
    writeInStrips(file, cube, {1, 1, 1, 1}, {.gzipLevel = 4, .component = SpectralComponent::Reflective});
    const SpectralImage back = readHdf5Cube(file);
    EXPECT_EQ(back.component, SpectralComponent::Reflective);
    expectBitExact(cube, back.cube);
}

TEST_F(Hdf5Cube, EqualsTheExrWritersValues) {
    SpectralCube cube = randomCube(9, 6, Grid{300, 740, 5}, 3);
    cube.data[17] = 0.0f;
    cube.data[18] = -1.5f;
    cube.data[19] = 1e-30f;  // a subnormal-adjacent value survives both
    writeSpectralExr(dir / "cube.exr", cube, {.compression = "zip"});
    writeHdf5Cube(dir / "cube.h5", cube, {.gzipLevel = 6});
    expectBitExact(readSpectralExr(dir / "cube.exr"), readHdf5Cube(dir / "cube.h5").cube);
}

TEST_F(Hdf5Cube, LayoutChunksAndAttributes) {
    const SpectralCube cube = randomCube(5, 2, Grid{500, 560, 10}, 4);
    const fs::path file = dir / "layout.h5";
    writeHdf5Cube(file, cube,
                  {.gzipLevel = 5, .attributes = {{"metamer:scene", "Macbeth, ünïcode"}, {"metamer:spp", "64"}}});
    hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    hid_t set = H5Dopen2(f, "cube", H5P_DEFAULT);
    ASSERT_GE(set, 0);
    hid_t space = H5Dget_space(set);
    hsize_t dims[3] = {};
    ASSERT_EQ(H5Sget_simple_extent_ndims(space), 3);
    H5Sget_simple_extent_dims(space, dims, nullptr);
    EXPECT_EQ(dims[0], 2u);
    EXPECT_EQ(dims[1], 5u);
    EXPECT_EQ(dims[2], 7u);
    hid_t type = H5Dget_type(set);
    EXPECT_GT(H5Tequal(type, H5T_IEEE_F32LE), 0);
    hid_t dcpl = H5Dget_create_plist(set);
    EXPECT_EQ(H5Pget_layout(dcpl), H5D_CHUNKED);
    hsize_t chunk[3] = {};
    ASSERT_EQ(H5Pget_chunk(dcpl, 3, chunk), 3);
    EXPECT_EQ(chunk[0], 1u);
    EXPECT_EQ(chunk[1], 5u);
    EXPECT_EQ(chunk[2], 7u);
    ASSERT_EQ(H5Pget_nfilters(dcpl), 2);  // shuffle, then deflate
    unsigned flags = 0, level = 0;
    size_t nValues = 1;
    EXPECT_EQ(H5Pget_filter2(dcpl, 0, &flags, nullptr, nullptr, 0, nullptr, nullptr), H5Z_FILTER_SHUFFLE);
    EXPECT_EQ(H5Pget_filter2(dcpl, 1, &flags, &nValues, &level, 0, nullptr, nullptr), H5Z_FILTER_DEFLATE);
    EXPECT_EQ(level, 5u);

    EXPECT_EQ(readStringAttribute(set, "units"), "W sr-1 m-2 nm-1");  // UDUNITS grammar
    EXPECT_EQ(readStringAttribute(set, "units_readable"), "W·sr⁻¹·m⁻²·nm⁻¹");
    EXPECT_EQ(readStringAttribute(set, "quantity"), "spectral radiance");
    EXPECT_EQ(readStringAttribute(set, "grid"), "500:560:10");
    EXPECT_EQ(readStringAttribute(set, "resampling"), "interpolate");
    EXPECT_EQ(readStringAttribute(set, "interleave"), "pixel ([row, column, band])");
    double bandWidth = 0;
    hid_t a = H5Aopen(set, "band_width_nm", H5P_DEFAULT);
    ASSERT_GE(a, 0);
    H5Aread(a, H5T_NATIVE_DOUBLE, &bandWidth);
    H5Aclose(a);
    EXPECT_EQ(bandWidth, 10.0);
    EXPECT_EQ(readStringAttribute(f, "metamer:scene"), "Macbeth, ünïcode");
    EXPECT_EQ(readStringAttribute(f, "metamer:spp"), "64");

    for (const char* name : {"wavelength_nm", "fwhm_nm"}) {
        hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
        ASSERT_GE(d, 0) << name;
        hid_t t = H5Dget_type(d);
        EXPECT_GT(H5Tequal(t, H5T_IEEE_F64LE), 0) << name;
        std::vector<double> v(7);
        ASSERT_GE(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
        for (int b = 0; b < 7; ++b)
            EXPECT_EQ(v[size_t(b)], std::strcmp(name, "fwhm_nm") == 0 ? 10.0 : 500.0 + 10.0 * b) << name << b;
        H5Tclose(t);
        H5Dclose(d);
    }
    H5Pclose(dcpl);
    H5Tclose(type);
    H5Sclose(space);
    H5Dclose(set);
    H5Fclose(f);
}

// What netCDF readers (h5netcdf, xarray) need to name the dimensions: a labelled dimension scale
// on each of /cube's axes, /wavelength holding the band centres in nm. tests/python/check_cube_formats.py
// opens the same layout with xarray.
TEST_F(Hdf5Cube, DimensionsAreLabelledScalesYXWavelength) {
    const SpectralCube cube = randomCube(5, 2, Grid{500, 560, 10}, 3);
    const fs::path file = dir / "scales.h5";
    writeHdf5Cube(file, cube);
    hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    hid_t set = H5Dopen2(f, "cube", H5P_DEFAULT);
    ASSERT_GE(set, 0);
    const char* names[3] = {"y", "x", "wavelength"};
    const hsize_t sizes[3] = {2, 5, 7};
    for (unsigned d = 0; d < 3; ++d) {
        char label[32] = {};
        ASSERT_GT(H5DSget_label(set, d, label, sizeof label), 0) << d;
        EXPECT_STREQ(label, names[d]);
        hid_t scale = H5Dopen2(f, names[d], H5P_DEFAULT);
        ASSERT_GE(scale, 0) << names[d];
        EXPECT_GT(H5DSis_scale(scale), 0) << names[d];
        EXPECT_GT(H5DSis_attached(set, scale, d), 0) << names[d];
        char scaleName[32] = {};
        ASSERT_GT(H5DSget_scale_name(scale, scaleName, sizeof scaleName), 0) << names[d];
        EXPECT_STREQ(scaleName, names[d]);
        hid_t space = H5Dget_space(scale);
        hsize_t n = 0;
        H5Sget_simple_extent_dims(space, &n, nullptr);
        EXPECT_EQ(n, sizes[d]) << names[d];
        H5Sclose(space);
        H5Dclose(scale);
    }
    // The wavelength coordinate in nm; /wavelength_nm and /fwhm_nm lie along the same dimension.
    hid_t wavelength = H5Dopen2(f, "wavelength", H5P_DEFAULT);
    std::vector<double> w(7);
    ASSERT_GE(H5Dread(wavelength, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, w.data()), 0);
    for (int b = 0; b < 7; ++b) EXPECT_EQ(w[size_t(b)], 500.0 + 10.0 * b);
    EXPECT_EQ(readStringAttribute(wavelength, "units"), "nm");
    for (const char* name : {"wavelength_nm", "fwhm_nm"}) {
        hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
        EXPECT_GT(H5DSis_attached(d, wavelength, 0), 0) << name;
        H5Dclose(d);
    }
    hid_t x = H5Dopen2(f, "x", H5P_DEFAULT);
    std::vector<int> columns(5);
    ASSERT_GE(H5Dread(x, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, columns.data()), 0);
    EXPECT_EQ(columns, (std::vector<int>{0, 1, 2, 3, 4}));
    H5Dclose(x);
    H5Dclose(wavelength);
    H5Dclose(set);
    H5Fclose(f);
    // Metamer reads its own file as before.
    expectBitExact(readHdf5Cube(file).cube, cube);
}

TEST_F(Hdf5Cube, WideRowsAreChunkedBy1024ColumnsAndUncompressedHasNoFilters) {
    const SpectralCube cube = randomCube(1500, 2, Grid{400, 420, 10}, 5);
    const fs::path file = dir / "wide.h5";
    writeInStrips(file, cube, {1, 1}, {});
    hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    hid_t set = H5Dopen2(f, "cube", H5P_DEFAULT);
    hid_t dcpl = H5Dget_create_plist(set);
    hsize_t chunk[3] = {};
    H5Pget_chunk(dcpl, 3, chunk);
    EXPECT_EQ(chunk[1], 1024u);
    EXPECT_EQ(H5Pget_nfilters(dcpl), 0);
    H5Pclose(dcpl);
    H5Dclose(set);
    H5Fclose(f);
    expectBitExact(cube, readHdf5Cube(file).cube);
}

TEST_F(Hdf5Cube, AbandonedWriterLeavesNoFile) {
    const SpectralCube cube = randomCube(4, 3, Grid{400, 500, 50}, 6);
    const int liveBefore = liveTempFileCount();
    {
        Hdf5CubeWriter writer(dir / "abandoned.h5", 4, 3, cube.grid, {.gzipLevel = 3});
        writer.writeRows(0, 2, cube.data.data());
        EXPECT_EQ(liveTempFileCount(), liveBefore + 1);
    }
    EXPECT_TRUE(namesIn().empty()) << ::testing::PrintToString(namesIn());
    EXPECT_EQ(liveTempFileCount(), liveBefore);
}

TEST_F(Hdf5Cube, WriterMisuseIsARuntimeErrorNamingThePath) {
    const Grid grid{400, 500, 50};
    const std::vector<float> rows(4 * 3 * 3, 1.0f);
    Hdf5CubeWriter writer(dir / "misuse.h5", 4, 3, grid);
    try {
        writer.writeRows(1, 1, rows.data());  // row 0 comes first
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::Failure);
        EXPECT_NE(e.message().find("misuse.h5"), std::string::npos) << e.message();
    }
    writer.writeRows(0, 2, rows.data());
    EXPECT_THROW(writer.commit(), Error);  // 2 of 3 rows
    EXPECT_THROW(Hdf5CubeWriter(dir / "bad.h5", 1, 1, grid, {.gzipLevel = 10}), Error);
    std::ofstream(dir / "blocker") << "a file where a folder should be";
    EXPECT_THROW(Hdf5CubeWriter(dir / "blocker" / "x.h5", 1, 1, grid), Error);
}

TEST_F(Hdf5Cube, ForeignFileWithoutOurAttributesReads) {
    // Integer wavelengths, a float64 cube, no grid or quantity attribute: what h5py users write.
    const fs::path file = dir / "foreign.h5";
    hid_t f = create(file);
    const std::vector<double> values = {0.5, 1.5, 2.5, 1e300, 4.5, 5.5};  // [1, 2, 3]
    dataset(f, "cube", H5T_IEEE_F64BE, {1, 2, 3}, H5T_NATIVE_DOUBLE, values.data(), true);
    const std::vector<int> nm = {450, 475, 500};
    dataset(f, "wavelength_nm", H5T_STD_I32LE, {3}, H5T_NATIVE_INT, nm.data());
    H5Fclose(f);
    const SpectralImage image = readHdf5Cube(file);
    EXPECT_EQ(image.component, SpectralComponent::Emissive);
    EXPECT_EQ(image.cube.grid, (Grid{450, 500, 25}));
    EXPECT_EQ(image.cube.width, 2);
    EXPECT_EQ(image.cube.height, 1);
    EXPECT_EQ(image.cube.at(0, 0, 0), 0.5f);
    EXPECT_EQ(image.cube.at(1, 0, 2), 5.5f);
    EXPECT_GE(image.cube.at(1, 0, 0), std::numeric_limits<float>::max());  // beyond float: max or +Inf
}

TEST_F(Hdf5Cube, OneBandKeepsItsStepThroughTheGridAttribute) {
    const SpectralCube cube = randomCube(2, 2, Grid{550, 550, 10}, 7);
    ASSERT_EQ(cube.bands(), 1);
    writeHdf5Cube(dir / "one.h5", cube);
    const SpectralImage back = readHdf5Cube(dir / "one.h5");
    EXPECT_EQ(back.cube.grid.step_nm, 10.0);
    expectBitExact(cube, back.cube);
}

TEST_F(Hdf5Cube, MalformedFilesAreInputErrorsNamingTheFileAndKey) {
    const std::vector<double> three = {400, 410, 420};
    auto read = [](const fs::path& p) { return [p] { readHdf5Cube(p); }; };

    expectInputError(read(dir / "missing.h5"), dir / "missing.h5", "", "not found");
    expectInputError(read(dir), dir, "", "is a folder, not a file");
    std::ofstream(dir / "text.h5") << "hello, not HDF5\n";
    expectInputError(read(dir / "text.h5"), dir / "text.h5", "", "not an HDF5 file");

    // Truncated: a valid file cut in half.
    const SpectralCube cube = randomCube(16, 16, Grid{400, 700, 10}, 8);
    writeHdf5Cube(dir / "whole.h5", cube);
    fs::copy_file(dir / "whole.h5", dir / "cut.h5");
    fs::resize_file(dir / "cut.h5", fs::file_size(dir / "whole.h5") / 2);
    expectInputError(read(dir / "cut.h5"), dir / "cut.h5", "", "truncated or damaged HDF5 file");

    writeForeign(dir / "no-wavelengths.h5", {2, 2, 3}, nullptr);
    expectInputError(read(dir / "no-wavelengths.h5"), dir / "no-wavelengths.h5", "/wavelength_nm", "missing");

    {
        hid_t f = create(dir / "no-cube.h5");
        dataset(f, "wavelength_nm", H5T_IEEE_F64LE, {3}, H5T_NATIVE_DOUBLE, three.data());
        H5Fclose(f);
    }
    expectInputError(read(dir / "no-cube.h5"), dir / "no-cube.h5", "/cube", "missing");

    {
        hid_t f = create(dir / "group.h5");
        H5Gclose(H5Gcreate2(f, "cube", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
        H5Fclose(f);
    }
    expectInputError(read(dir / "group.h5"), dir / "group.h5", "/cube", "not a readable dataset");

    writeForeign(dir / "rank2.h5", {4, 3}, &three);
    expectInputError(read(dir / "rank2.h5"), dir / "rank2.h5", "/cube", "rank 2");

    writeForeign(dir / "count.h5", {2, 2, 4}, &three);
    expectInputError(read(dir / "count.h5"), dir / "count.h5", "/wavelength_nm", "3 wavelengths but /cube has 4 bands");

    const std::vector<double> gappy = {400, 410, 430};
    writeForeign(dir / "gappy.h5", {2, 2, 3}, &gappy);
    expectInputError(read(dir / "gappy.h5"), dir / "gappy.h5", "/wavelength_nm", "not on a uniform grid");

    const std::vector<double> nan = {400, NAN, 420};
    writeForeign(dir / "nan.h5", {2, 2, 3}, &nan);
    expectInputError(read(dir / "nan.h5"), dir / "nan.h5", "/wavelength_nm", "is not a wavelength");

    const std::vector<double> down = {420, 410, 400};
    writeForeign(dir / "down.h5", {2, 2, 3}, &down);
    expectInputError(read(dir / "down.h5"), dir / "down.h5", "/wavelength_nm", "not increasing");

    const std::vector<double> none;
    writeForeign(dir / "empty.h5", {2, 0, 3}, &none);
    expectInputError(read(dir / "empty.h5"), dir / "empty.h5", "/cube", "empty");

    {
        hid_t f = create(dir / "ints.h5");
        const std::vector<int> v(12, 1);
        dataset(f, "cube", H5T_STD_I32LE, {2, 2, 3}, H5T_NATIVE_INT, v.data());
        dataset(f, "wavelength_nm", H5T_IEEE_F64LE, {3}, H5T_NATIVE_DOUBLE, three.data());
        H5Fclose(f);
    }
    expectInputError(read(dir / "ints.h5"), dir / "ints.h5", "/cube", "integer values");

    writeForeign(dir / "quantity.h5", {1, 1, 3}, &three, "radiance");
    expectInputError(read(dir / "quantity.h5"), dir / "quantity.h5", "/cube.quantity", "'radiance'");
}

TEST_F(Hdf5Cube, HugeShapeIsRefusedBeforeAllocating) {
    // A chunked dataset stores nothing until written: a tiny file can declare 2^40 values.
    const fs::path file = dir / "huge.h5";
    hid_t f = create(file);
    dataset(f, "cube", H5T_IEEE_F32LE, {1 << 20, 1 << 10, 1 << 10}, H5T_NATIVE_FLOAT, nullptr, true);
    std::vector<double> wl(1 << 10);
    for (size_t i = 0; i < wl.size(); ++i) wl[i] = 400 + double(i);
    dataset(f, "wavelength_nm", H5T_IEEE_F64LE, {wl.size()}, H5T_NATIVE_DOUBLE, wl.data());
    H5Fclose(f);
    ASSERT_LT(fs::file_size(file), 1u << 20);
    expectInputError([&] { readHdf5Cube(file); }, file, "/cube", "more than 2^34 values");
}

// Issue 30, class 6: HDF5 reads no file on a cube's behalf. External storage (a FIFO hung the
// reader; /dev/zero), external, soft and user-defined links, virtual datasets: each an input error
// naming the file, the dataset and what it found, before HDF5 opens anything else.
TEST_F(Hdf5Cube, IndirectionToOtherFilesIsRefusedNamingWhatWasFound) {
    const std::string outside = (dir / "outside.h5").string();
    writeForeign(outside, {2, 2, 3}, nullptr);
    auto expectRefused = [&](const fs::path& file, const char* key, const std::string& found) {
        SCOPED_TRACE(file.string());
        const std::string text = readInChild(file);
        EXPECT_NE(text.find(file.string() + ": " + key + ": " + found), std::string::npos) << text;
        EXPECT_NE(text.find("refused"), std::string::npos) << text;
    };

    // External storage in a FIFO: refused from the dataset's properties, never opened.
    const fs::path fifo = dir / "values.fifo";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    writeWith(dir / "fifo.h5", [&](hid_t f, const std::vector<hsize_t>& d) { externalCube(f, d, fifo); });
    expectRefused(dir / "fifo.h5", "/cube", "keeps its values in 1 external file ('" + fifo.string() + "')");
    writeWith(dir / "zero.h5", [&](hid_t f, const std::vector<hsize_t>& d) { externalCube(f, d, "/dev/zero"); });
    expectRefused(dir / "zero.h5", "/cube", "keeps its values in 1 external file ('/dev/zero')");

    writeWith(dir / "elink.h5", [&](hid_t f, const std::vector<hsize_t>&) {
        ASSERT_GE(H5Lcreate_external(outside.c_str(), "/cube", f, "cube", H5P_DEFAULT, H5P_DEFAULT), 0);
    });
    expectRefused(dir / "elink.h5", "/cube", "is an external link to '" + outside + ":/cube'");
    // The external link to a FIFO: HDF5 would open it as a file.
    writeWith(dir / "elink-fifo.h5", [&](hid_t f, const std::vector<hsize_t>&) {
        ASSERT_GE(H5Lcreate_external(fifo.c_str(), "/cube", f, "cube", H5P_DEFAULT, H5P_DEFAULT), 0);
    });
    expectRefused(dir / "elink-fifo.h5", "/cube", "is an external link to '" + fifo.string() + ":/cube'");

    writeWith(dir / "soft.h5", [&](hid_t f, const std::vector<hsize_t>& d) {
        std::vector<float> zeros(12, 0.0f);
        dataset(f, "data", H5T_IEEE_F32LE, d, H5T_NATIVE_FLOAT, zeros.data());
        ASSERT_GE(H5Lcreate_soft("/data", f, "cube", H5P_DEFAULT, H5P_DEFAULT), 0);
    });
    expectRefused(dir / "soft.h5", "/cube", "is a soft link to '/data'");

    writeWith(dir / "virtual.h5", [&](hid_t f, const std::vector<hsize_t>& d) { virtualCube(f, d, fifo); });
    expectRefused(dir / "virtual.h5", "/cube", "is a virtual dataset (1 source, the first in '" + fifo.string() + "')");

    // /wavelength_nm is checked the same way.
    {
        hid_t f = create(dir / "wl-link.h5");
        std::vector<float> zeros(12, 0.0f);
        dataset(f, "cube", H5T_IEEE_F32LE, {2, 2, 3}, H5T_NATIVE_FLOAT, zeros.data());
        ASSERT_GE(H5Lcreate_external(outside.c_str(), "/wavelength_nm", f, "wavelength_nm", H5P_DEFAULT, H5P_DEFAULT), 0);
        H5Fclose(f);
    }
    expectRefused(dir / "wl-link.h5", "/wavelength_nm", "is an external link");

    // The cube file itself a FIFO: refused before HDF5 opens it.
    const std::string text = readInChild(fifo);
    EXPECT_NE(text.find("is not a regular file (a FIFO)"), std::string::npos) << text;
}

// HDF5 puts its signature after a user block (512, 1024, 2048, ... bytes): such a file is HDF5.
TEST_F(Hdf5Cube, AUserBlockBeforeTheSignatureReads) {
    for (hsize_t block : {512, 2048}) {
        const fs::path file = dir / fmt::format("user-block-{}.h5", block);
        writeWith(
            file,
            [](hid_t f, const std::vector<hsize_t>& d) {
                const std::vector<float> values(12, 0.25f);
                dataset(f, "cube", H5T_IEEE_F32LE, d, H5T_NATIVE_FLOAT, values.data());
            },
            block);
        {
            std::ifstream in(file, std::ios::binary);
            char head[4] = {};
            in.read(head, 4);
            ASSERT_NE(std::string(head, 4), "\x89HDF") << "the signature should not be at offset 0";
        }
        EXPECT_TRUE(hasHdf5Signature(file));
        EXPECT_EQ(cubeFormatOf(file), CubeFormat::Hdf5);
        const SpectralImage image = readSpectralImage(file);
        EXPECT_EQ(image.cube.grid, (Grid{400, 420, 10}));
        EXPECT_EQ(image.cube.at(1, 1, 2), 0.25f);
    }
    std::ofstream(dir / "text.h5") << std::string(4096, 'x');
    EXPECT_FALSE(hasHdf5Signature(dir / "text.h5"));
    EXPECT_FALSE(hasHdf5Signature(dir));
}

// A file is the same bytes whenever it is written: no object carries HDF5's modification time
// (a batch's jobs, split into shards or re-rendered alone, give identical files; docs/batch.md).
TEST_F(Hdf5Cube, TheSameCubeWrittenASecondApartIsTheSameBytes) {
    const SpectralCube cube = randomCube(6, 4, Grid{400, 700, 10}, 3);
    writeInStrips(dir / "a.h5", cube, {4}, {.gzipLevel = 4});
    {
        AradMatWriter arad(dir / "a.mat", cube.width, cube.height, cube.grid, {});
        arad.writeRows(0, cube.height, cube.pixel(0, 0));
        commitTogether(arad.finish());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // HDF5's times have one-second steps
    writeInStrips(dir / "b.h5", cube, {4}, {.gzipLevel = 4});
    {
        AradMatWriter arad(dir / "b.mat", cube.width, cube.height, cube.grid, {});
        arad.writeRows(0, cube.height, cube.pixel(0, 0));
        commitTogether(arad.finish());
    }
    EXPECT_EQ(test::slurp(dir / "a.h5"), test::slurp(dir / "b.h5"));
    EXPECT_EQ(test::slurp(dir / "a.mat"), test::slurp(dir / "b.mat"));
}
