#include "io/hdf5_cube.h"

#include "core/error.h"
#include "core/file_reads.h"
#include "core/memory_limits.h"
#include "io/atomic_file.h"
#include "spectral/resampling.h"

#include <hdf5.h>
#include <hdf5_hl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

namespace metamer {

namespace {

// `units` in UDUNITS' grammar, which CF readers (xarray with cf-units or pint, Panoply, ncdump
// users) parse; the same with superscripts in `units_readable`.
constexpr const char* kRadianceUnits = "W sr-1 m-2 nm-1";
constexpr const char* kRadianceUnitsReadable = "W·sr⁻¹·m⁻²·nm⁻¹";
constexpr const char* kInterleave = "pixel ([row, column, band])";
constexpr hsize_t kMaxChunkColumns = 1024;
constexpr uint64_t kMaxValues = uint64_t(1) << 34;  // 64 GiB of float32: refused before allocating
constexpr char kSignature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};

// An HDF5 identifier, closed when it goes out of scope.
class Handle {
public:
    using Closer = herr_t (*)(hid_t);
    Handle() = default;
    Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
    Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)), closer_(o.closer_) {}
    Handle& operator=(Handle&& o) noexcept {
        if (this != &o) {
            close();
            id_ = std::exchange(o.id_, H5I_INVALID_HID);
            closer_ = o.closer_;
        }
        return *this;
    }
    ~Handle() { close(); }
    hid_t get() const { return id_; }
    bool valid() const { return id_ >= 0; }
    // Closes now; false when HDF5 reports an error (for a file: its last writes failed).
    bool close() {
        hid_t id = std::exchange(id_, H5I_INVALID_HID);
        return id < 0 || closer_(id) >= 0;
    }

private:
    hid_t id_ = H5I_INVALID_HID;
    Closer closer_ = nullptr;
};

// HDF5 prints its whole error stack to stderr by default; we report one line of our own instead.
// In a thread-safe build the setting belongs to the calling thread, so every entry point makes it.
void quietHdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

// The most specific message on this thread's HDF5 error stack (then cleared), or "".
std::string hdf5Detail() {
    std::string detail;
    H5Ewalk2(
        H5E_DEFAULT, H5E_WALK_UPWARD,
        [](unsigned n, const H5E_error2_t* e, void* out) -> herr_t {
            if (n == 0 && e->desc) *static_cast<std::string*>(out) = e->desc;
            return 0;
        },
        &detail);
    H5Eclear2(H5E_DEFAULT);
    return detail;
}

std::string withDetail(const std::string& detail) { return detail.empty() ? "" : ": " + detail; }

// File access without HDF5's file locks: our temporary file has no other writer and a reader needs
// none, and where the file system has no locks (some cluster mounts) HDF5 1.10 would refuse to
// open anything. The one-file POSIX driver, whatever HDF5_DRIVER says: the family, multi and split
// drivers would open further files beside the one named. Invalid (the default properties) if it
// cannot be made.
Handle fileAccess() {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    if (fapl.valid()) H5Pset_fapl_sec2(fapl.get());
#if H5_VERSION_GE(1, 10, 7)
    if (fapl.valid()) H5Pset_file_locking(fapl.get(), false, true);
#endif
    return fapl;
}

hid_t orDefault(const Handle& properties) { return properties.valid() ? properties.get() : H5P_DEFAULT; }

// --- Writing -----------------------------------------------------------------------------------

[[noreturn]] void failWrite(const fs::path& path, const char* what) {
    failRuntime("cannot write '{}': HDF5 could not {}{}", path.string(), what, withDetail(hdf5Detail()));
}

Handle made(hid_t id, Handle::Closer closer, const fs::path& path, const char* what) {
    if (id < 0) failWrite(path, what);
    return Handle(id, closer);
}

void check(herr_t status, const fs::path& path, const char* what) {
    if (status < 0) failWrite(path, what);
}

// A variable-length UTF-8 string (what h5py reads as str); a later attribute of the same name wins.
void writeStringAttribute(hid_t object, const std::string& name, const std::string& value, const fs::path& path) {
    Handle type = made(H5Tcopy(H5T_C_S1), H5Tclose, path, "make a string type");
    check(H5Tset_size(type.get(), H5T_VARIABLE), path, "make a string type");
    check(H5Tset_cset(type.get(), H5T_CSET_UTF8), path, "make a string type");
    Handle space = made(H5Screate(H5S_SCALAR), H5Sclose, path, "make a scalar dataspace");
    if (H5Aexists(object, name.c_str()) > 0) check(H5Adelete(object, name.c_str()), path, "replace an attribute");
    Handle attribute = made(H5Acreate2(object, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
                            H5Aclose, path, "create a string attribute");
    const char* text = value.c_str();
    check(H5Awrite(attribute.get(), type.get(), &text), path, "write a string attribute");
}

void writeDoubleAttribute(hid_t object, const char* name, double value, const fs::path& path) {
    Handle space = made(H5Screate(H5S_SCALAR), H5Sclose, path, "make a scalar dataspace");
    Handle attribute = made(H5Acreate2(object, name, H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                            H5Aclose, path, "create a number attribute");
    check(H5Awrite(attribute.get(), H5T_NATIVE_DOUBLE, &value), path, "write a number attribute");
}

// Dataset properties without modification times: HDF5 stamps every object header with the time it
// was written unless told not to, and a file must be the same bytes however and whenever its job
// ran (a batch split into shards, a job re-rendered alone: docs/batch.md).
Handle untimed(hid_t propertyClass, const fs::path& path) {
    Handle p = made(H5Pcreate(propertyClass), H5Pclose, path, "make object properties");
    check(H5Pset_obj_track_times(p.get(), false), path, "leave out modification times");
    return p;
}

// A float64 [bands] dataset in nm; returned open, for dimension scales.
Handle writeDoubles(hid_t file, const char* name, const std::vector<double>& values, const fs::path& path) {
    const hsize_t n = values.size();
    Handle space = made(H5Screate_simple(1, &n, nullptr), H5Sclose, path, "make a dataspace");
    const Handle dcpl = untimed(H5P_DATASET_CREATE, path);
    Handle set = made(H5Dcreate2(file, name, H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
                      H5Dclose, path, "create a wavelength dataset");
    check(H5Dwrite(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), path,
          "write a wavelength dataset");
    writeStringAttribute(set.get(), "units", "nm", path);
    return set;
}

// /y or /x: the row or column index 0 .. n−1, as int32, so that every dimension of /cube has a
// scale and netCDF readers need no made-up ("phony") dimension names.
Handle writeIndices(hid_t file, const char* name, int n, const char* longName, const fs::path& path) {
    const hsize_t size = hsize_t(n);
    std::vector<int32_t> index(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) index[size_t(i)] = i;
    Handle space = made(H5Screate_simple(1, &size, nullptr), H5Sclose, path, "make a dataspace");
    const Handle dcpl = untimed(H5P_DATASET_CREATE, path);
    Handle set = made(H5Dcreate2(file, name, H5T_STD_I32LE, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
                      H5Dclose, path, "create a pixel index dataset");
    check(H5Dwrite(set.get(), H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, index.data()), path,
          "write a pixel index dataset");
    writeStringAttribute(set.get(), "long_name", longName, path);
    return set;
}

// Makes `scale` the dimension scale named `name` (HDF5's DS convention, which netCDF-4 and so
// h5netcdf and xarray read as a dimension with coordinates) and attaches it to `dimension` of each
// dataset in `users`.
void attachScale(const Handle& scale, const char* name, std::initializer_list<std::pair<hid_t, unsigned>> users,
                 const fs::path& path) {
    check(H5DSset_scale(scale.get(), name), path, "make a dimension scale");
    for (const auto& [set, dimension] : users)
        check(H5DSattach_scale(set, scale.get(), dimension), path, "attach a dimension scale");
}

}  // namespace

struct Hdf5CubeWriter::Impl {
    fs::path path;
    int width = 0, height = 0, bands = 0, nextRow = 0;
    AtomicOutput out;  // declared first, so destroyed last: the handles below close the file before
    Handle file, cube, fileSpace;
    explicit Impl(const fs::path& p) : path(p), out(p) {}
};

Hdf5CubeWriter::Hdf5CubeWriter(const fs::path& path, int width, int height, const Grid& grid,
                               const Hdf5WriteOptions& options)
    : impl_(std::make_unique<Impl>(path)) {
    quietHdf5();
    Impl& m = *impl_;
    m.width = width;
    m.height = height;
    m.bands = grid.bands();
    if (width <= 0 || height <= 0 || m.bands <= 0)
        failRuntime("cannot write '{}': a {}×{} cube with {} bands", path.string(), width, height, m.bands);
    if (options.gzipLevel < 0 || options.gzipLevel > 9)
        failInput(Where{"", "gzip"}, "gzip level {} is not 0 (none) to 9", options.gzipLevel);
    if (options.gzipLevel > 0 && H5Zfilter_avail(H5Z_FILTER_DEFLATE) <= 0)
        failRuntime("cannot write '{}': this HDF5 library has no gzip (deflate) filter", path.string());

    const Handle fapl = fileAccess();
    const Handle fcpl = untimed(H5P_FILE_CREATE, path);
    m.file = made(H5Fcreate(m.out.tempPath().c_str(), H5F_ACC_TRUNC, fcpl.get(), orDefault(fapl)), H5Fclose, path,
                  "create the file");
    const hsize_t dims[3] = {hsize_t(height), hsize_t(width), hsize_t(m.bands)};
    m.fileSpace = made(H5Screate_simple(3, dims, nullptr), H5Sclose, path, "make the cube's dataspace");
    Handle dcpl = untimed(H5P_DATASET_CREATE, path);
    // One chunk is (part of) one row with all its bands: each strip writes whole chunks, never
    // reading one back, and a reader of a pixel's spectrum decompresses one chunk.
    const hsize_t chunk[3] = {1, std::min(hsize_t(width), kMaxChunkColumns), hsize_t(m.bands)};
    check(H5Pset_chunk(dcpl.get(), 3, chunk), path, "set the chunk size");
    if (options.gzipLevel > 0) {
        // Shuffle first: grouping the floats' bytes by significance roughly doubles what gzip saves.
        check(H5Pset_shuffle(dcpl.get()), path, "set the shuffle filter");
        check(H5Pset_deflate(dcpl.get(), unsigned(options.gzipLevel)), path, "set the gzip filter");
    }
    check(H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER), path, "set the fill time");  // every value is written
    m.cube = made(H5Dcreate2(m.file.get(), "cube", H5T_IEEE_F32LE, m.fileSpace.get(), H5P_DEFAULT, dcpl.get(),
                             H5P_DEFAULT),
                  H5Dclose, path, "create /cube");

    const bool reflective = options.component == SpectralComponent::Reflective;
    writeStringAttribute(m.cube.get(), "units", reflective ? "1" : kRadianceUnits, path);
    writeStringAttribute(m.cube.get(), "units_readable", reflective ? "1" : kRadianceUnitsReadable, path);
    writeStringAttribute(m.cube.get(), "quantity", reflective ? "reflectance" : "spectral radiance", path);
    writeStringAttribute(m.cube.get(), "grid", grid.str(), path);
    writeDoubleAttribute(m.cube.get(), "band_width_nm", grid.step_nm, path);
    writeStringAttribute(m.cube.get(), "resampling", resamplingName(grid.resampling), path);
    writeStringAttribute(m.cube.get(), "interleave", kInterleave, path);
    const Handle wavelengthNm = writeDoubles(m.file.get(), "wavelength_nm", grid.wavelengths(), path);
    const Handle fwhm = writeDoubles(m.file.get(), "fwhm_nm", std::vector<double>(size_t(m.bands), grid.step_nm), path);
    // The dimensions, named and with coordinates, for netCDF readers (docs/io.md, "HDF5"): /wavelength
    // repeats /wavelength_nm, which Metamer and earlier readers keep reading, under the name the
    // dimension takes (h5netcdf names a dimension after its scale's dataset).
    const Handle wavelength = writeDoubles(m.file.get(), "wavelength", grid.wavelengths(), path);
    writeStringAttribute(wavelength.get(), "long_name", "band centre wavelength", path);
    writeStringAttribute(wavelength.get(), "standard_name", "radiation_wavelength", path);
    const Handle rows = writeIndices(m.file.get(), "y", height, "pixel row, 0 at the top", path);
    const Handle columns = writeIndices(m.file.get(), "x", width, "pixel column, 0 at the left", path);
    attachScale(rows, "y", {{m.cube.get(), 0}}, path);
    attachScale(columns, "x", {{m.cube.get(), 1}}, path);
    attachScale(wavelength, "wavelength", {{m.cube.get(), 2}, {wavelengthNm.get(), 0}, {fwhm.get(), 0}}, path);
    const char* labels[3] = {"y", "x", "wavelength"};
    for (unsigned d = 0; d < 3; ++d) check(H5DSset_label(m.cube.get(), d, labels[d]), path, "label a dimension");
    for (const auto& [name, value] : options.attributes) writeStringAttribute(m.file.get(), name, value, path);
}

Hdf5CubeWriter::~Hdf5CubeWriter() {
    quietHdf5();  // closing an abandoned file may fail; the temporary file goes anyway (AtomicOutput)
}

void Hdf5CubeWriter::writeRows(int firstRow, int rows, const float* data) {
    quietHdf5();
    Impl& m = *impl_;
    if (!m.cube.valid() || firstRow != m.nextRow || rows <= 0 || firstRow > m.height - rows)
        failRuntime("cannot write '{}': rows {}..{} out of order (next is {}, height {})", m.path.string(), firstRow,
                    int64_t(firstRow) + rows, m.nextRow, m.height);
    const hsize_t start[3] = {hsize_t(firstRow), 0, 0};
    const hsize_t count[3] = {hsize_t(rows), hsize_t(m.width), hsize_t(m.bands)};
    check(H5Sselect_hyperslab(m.fileSpace.get(), H5S_SELECT_SET, start, nullptr, count, nullptr), m.path,
          "select rows");
    Handle memory = made(H5Screate_simple(3, count, nullptr), H5Sclose, m.path, "make a dataspace");
    check(H5Dwrite(m.cube.get(), H5T_NATIVE_FLOAT, memory.get(), m.fileSpace.get(), H5P_DEFAULT, data), m.path,
          "write rows");
    m.nextRow = firstRow + rows;
}

std::vector<AtomicOutput*> Hdf5CubeWriter::finish() {
    quietHdf5();
    Impl& m = *impl_;
    if (m.nextRow != m.height)
        failRuntime("cannot write '{}': {} of {} rows written", m.path.string(), m.nextRow, m.height);
    if (m.out.committed()) return {};
    // Closing the file flushes the chunks still in HDF5's cache: its failure is a failed write.
    const bool cubeClosed = m.cube.close();
    const bool spaceClosed = m.fileSpace.close();
    if (!m.file.close() || !cubeClosed || !spaceClosed) failWrite(m.path, "finish the file");
    return {&m.out};
}

void Hdf5CubeWriter::commit() { commitTogether(finish()); }

void writeHdf5Cube(const fs::path& path, const SpectralCube& cube, const Hdf5WriteOptions& options) {
    const size_t count = static_cast<size_t>(cube.width) * cube.height * cube.bands();
    if (cube.width <= 0 || cube.height <= 0 || cube.bands() <= 0 || cube.data.size() != count)
        failRuntime("cannot write '{}': cube is {}×{} with {} bands but holds {} values", path.string(), cube.width,
                    cube.height, cube.bands(), cube.data.size());
    Hdf5CubeWriter writer(path, cube.width, cube.height, cube.grid, options);
    writer.writeRows(0, cube.height, cube.data.data());
    writer.commit();
}

// --- The ARAD layout (MATLAB v7.3) ---------------------------------------------------------------

namespace {

constexpr int kAradBands = 31;
const Grid kAradGrid{400, 700, 10};

// A fixed-length ASCII string attribute: MATLAB's MATLAB_class must be one.
void writeFixedStringAttribute(hid_t object, const char* name, const std::string& value, const fs::path& path) {
    Handle type = made(H5Tcopy(H5T_C_S1), H5Tclose, path, "make a string type");
    check(H5Tset_size(type.get(), value.size()), path, "make a string type");
    Handle space = made(H5Screate(H5S_SCALAR), H5Sclose, path, "make a scalar dataspace");
    Handle attribute = made(H5Acreate2(object, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
                            path, "create an attribute");
    check(H5Awrite(attribute.get(), type.get(), value.data()), path, "write an attribute");
}

// A MATLAB array: HDF5 dims are MATLAB's reversed.
void writeMatlabArray(hid_t file, const char* name, hid_t fileType, hid_t memoryType, const char* matlabClass,
                      std::initializer_list<hsize_t> dims, const void* data, const fs::path& path) {
    const std::vector<hsize_t> d(dims);
    Handle space = made(H5Screate_simple(int(d.size()), d.data(), nullptr), H5Sclose, path, "make a dataspace");
    const Handle dcpl = untimed(H5P_DATASET_CREATE, path);
    Handle set = made(H5Dcreate2(file, name, fileType, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), H5Dclose,
                      path, "create a dataset");
    check(H5Dwrite(set.get(), memoryType, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), path, "write a dataset");
    writeFixedStringAttribute(set.get(), "MATLAB_class", matlabClass, path);
}

}  // namespace

struct AradMatWriter::Impl {
    fs::path path;
    int width = 0, height = 0, nextRow = 0, renderBands = 0;
    BandWeights weights;
    StringAttributes attributes;
    std::vector<float> bands;  // [31][columns][rows]: MATLAB's rows × columns × 31, column-major
    AtomicOutput out;
    explicit Impl(const fs::path& p) : path(p), out(p) {}
};

AradMatWriter::AradMatWriter(const fs::path& path, int width, int height, const Grid& grid,
                             const StringAttributes& attributes)
    : impl_(std::make_unique<Impl>(path)) {
    Impl& m = *impl_;
    m.width = width;
    m.height = height;
    m.attributes = attributes;
    if (grid.start_nm > 400.0 + kCoincidence_nm || grid.end_nm < 700.0 - kCoincidence_nm)
        failInput(Where{"", "--format"},
                  "the ARAD layout holds 400–700 nm in 10 nm bands; the render's grid {} does not reach {}: render "
                  "with a grid that covers it (e.g. --grid 400:700:10)",
                  grid.str(), grid.start_nm > 400.0 ? "400 nm" : "700 nm");
    const uint64_t values = uint64_t(width) * uint64_t(height) * kAradBands;
    if (width <= 0 || height <= 0) failRuntime("cannot write '{}': a {}×{} ARAD cube", path.string(), width, height);
    // The 31 bands of the whole image are held until the end: within the quarter of the machine a
    // decoded image may take, or refused before the render starts.
    if (values > kMaxValues || values * sizeof(float) > decodedImageLimitBytes())
        failInput(Where{"", "--format"}, "the ARAD layout holds the whole {}×{} image's 31 bands ({}) until it is written; "
                  "the limit is {}, a quarter of this machine's memory: render it smaller, or as exr or hdf5",
                  width, height, memorySize(values * sizeof(float)), memorySize(decodedImageLimitBytes()));
    m.renderBands = grid.bands();
    m.weights = bandWeights(grid.wavelengths(), kAradGrid);
    m.bands.assign(values, 0.0f);
}

AradMatWriter::~AradMatWriter() { quietHdf5(); }

void AradMatWriter::writeRows(int firstRow, int rows, const float* data) {
    Impl& m = *impl_;
    if (firstRow != m.nextRow || rows <= 0 || firstRow > m.height - rows)
        failRuntime("cannot write '{}': rows {}..{} out of order (next is {}, height {})", m.path.string(), firstRow,
                    int64_t(firstRow) + rows, m.nextRow, m.height);
    for (int r = 0; r < rows; ++r)
        for (int x = 0; x < m.width; ++x) {
            const float* px = data + (size_t(r) * size_t(m.width) + size_t(x)) * size_t(m.renderBands);
            const size_t y = size_t(firstRow + r);
            for (size_t b = 0; b < size_t(kAradBands); ++b)
                m.bands[(b * size_t(m.width) + size_t(x)) * size_t(m.height) + y] = float(m.weights.at(b, px));
        }
    m.nextRow = firstRow + rows;
}

std::vector<AtomicOutput*> AradMatWriter::finish() {
    quietHdf5();
    Impl& m = *impl_;
    if (m.nextRow != m.height)
        failRuntime("cannot write '{}': {} of {} rows written", m.path.string(), m.nextRow, m.height);
    if (m.out.committed()) return {};
    // The divisor: the cube's largest value (1 for a black image, which stays 0).
    float peak = 0.0f;
    for (float v : m.bands) peak = std::max(peak, v);
    const double normFactor = peak > 0.0f ? double(peak) : 1.0;
    for (float& v : m.bands) v = float(double(v) / normFactor);
    {
        // MATLAB's header takes the first 512 bytes: the HDF5 file starts after a user block.
        Handle fcpl = untimed(H5P_FILE_CREATE, m.path);
        check(H5Pset_userblock(fcpl.get(), 512), m.path, "reserve MATLAB's header");
        const Handle fapl = fileAccess();
        Handle file = made(H5Fcreate(m.out.tempPath().c_str(), H5F_ACC_TRUNC, fcpl.get(), orDefault(fapl)), H5Fclose,
                           m.path, "create the file");
        writeMatlabArray(file.get(), "cube", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, "single",
                         {hsize_t(kAradBands), hsize_t(m.width), hsize_t(m.height)}, m.bands.data(), m.path);
        const std::vector<double> centres = kAradGrid.wavelengths();
        writeMatlabArray(file.get(), "bands", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, "double", {hsize_t(kAradBands), 1},
                         centres.data(), m.path);
        writeMatlabArray(file.get(), "norm_factor", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, "double", {1, 1}, &normFactor,
                         m.path);
        for (const auto& [name, value] : m.attributes) writeStringAttribute(file.get(), name, value, m.path);
        if (!file.close()) failWrite(m.path, "finish the file");
    }
    // The header: 116 bytes of text, 8 of subsystem offset, the version 0x0200 and the endian mark "IM".
    std::string header = "MATLAB 7.3 MAT-file, Platform: GLNXA64, Created by: Metamer (ARAD layout), HDF5 schema 1.00 .";
    header.resize(116, ' ');
    header.append(8, ' ');
    header += std::string("\x00\x02", 2) + "IM";
    header.resize(512, '\0');
    std::fstream f(m.out.tempPath(), std::ios::in | std::ios::out | std::ios::binary);
    if (!f || !f.write(header.data(), std::streamsize(header.size())) || !f.flush())
        failRuntime("cannot write '{}': the MATLAB header", m.path.string());
    m.bands = {};
    return {&m.out};
}

// --- Reading -----------------------------------------------------------------------------------

bool hasHdf5Signature(const fs::path& path) {
    std::error_code ec;
    if (!fs::is_regular_file(fs::status(path, ec))) return false;  // a FIFO would block the read
    const uintmax_t size = fs::file_size(path, ec);
    std::ifstream in(path, std::ios::binary);
    if (!in || ec) return false;
    for (uintmax_t offset = 0; offset + sizeof kSignature <= size; offset = offset ? offset * 2 : 512) {
        char bytes[sizeof kSignature] = {};
        in.seekg(std::streamoff(offset));
        if (!in.read(bytes, sizeof bytes)) return false;
        if (std::equal(bytes, bytes + sizeof bytes, kSignature)) return true;
    }
    return false;
}

namespace {

const char* typeClassName(H5T_class_t c) {
    switch (c) {
        case H5T_INTEGER: return "integer";
        case H5T_FLOAT: return "floating-point";
        case H5T_STRING: return "string";
        case H5T_COMPOUND: return "compound";
        case H5T_ENUM: return "enum";
        case H5T_ARRAY: return "array";
        case H5T_VLEN: return "variable-length";
        default: return "non-numeric";
    }
}

// An open dataset and its shape; input errors name the file and the dataset.
struct Dataset {
    Handle set;
    std::vector<hsize_t> dims;
    H5T_class_t typeClass = H5T_NO_CLASS;
};

// --- What HDF5 would read besides the file -----------------------------------------------------
// An HDF5 file can make the library read other files: an external link opens another HDF5 file, a
// dataset with external storage reads its values from raw files by name (a FIFO blocks for ever,
// /dev/zero never ends), a virtual dataset maps datasets of other files. None of those files would
// pass requireRegularFile, a scene's folder rule (--allow-outside-paths) or the batch digest
// (noteFileRead), so we refuse them, naming what was found (docs/io.md, "Reading cubes"). Soft
// links are refused too: /cube and /wavelength_nm must be the datasets themselves.

// A link's target as text, for messages ("" if unreadable).
std::string linkTarget(hid_t file, const char* name, const H5L_info_t& info, hid_t lapl) {
    const size_t size = info.u.val_size;
    if (size == 0 || size > (size_t(1) << 16)) return "";
    std::vector<char> value(size + 1, '\0');
    if (H5Lget_val(file, name, value.data(), size, lapl) < 0) return "";
    if (info.type == H5L_TYPE_SOFT) return std::string(value.data());
    const char* targetFile = nullptr;
    const char* targetObject = nullptr;
    if (H5Lunpack_elink_val(value.data(), size, nullptr, &targetFile, &targetObject) < 0) return "";
    return fmt::format("{}:{}", targetFile ? targetFile : "?", targetObject ? targetObject : "?");
}

// The link `name` in the root group must be a hard link.
void requireHardLink(hid_t file, const char* name, const Where& where, hid_t lapl) {
    H5L_info_t info;
    if (H5Lget_info(file, name, &info, lapl) < 0)
        failInput(where, "is not a readable link{}", withDetail(hdf5Detail()));
    if (info.type == H5L_TYPE_HARD) return;
    const std::string target = linkTarget(file, name, info, lapl);
    hdf5Detail();
    const std::string to = target.empty() ? "" : fmt::format(" to '{}'", target);
    if (info.type == H5L_TYPE_EXTERNAL)
        failInput(where, "is an external link{}: refused, Metamer reads no file an HDF5 file names (store the "
                         "dataset itself in this file)", to);
    if (info.type == H5L_TYPE_SOFT)
        failInput(where, "is a soft link{}: refused, the dataset must be stored under this name (a hard link)", to);
    failInput(where, "is a user-defined link (type {}): refused, the dataset must be stored under this name",
              int(info.type));
}

// The dataset's values must be stored in this file: no external storage, no virtual layout.
void requireStoredHere(hid_t set, const Where& where) {
    Handle dcpl(H5Dget_create_plist(set), H5Pclose);
    if (!dcpl.valid()) failInput(where, "has unreadable storage properties{}", withDetail(hdf5Detail()));
    const int external = H5Pget_external_count(dcpl.get());
    if (external < 0) failInput(where, "has unreadable storage properties{}", withDetail(hdf5Detail()));
    if (external > 0) {
        char name[1024] = {};
        off_t offset = 0;
        hsize_t size = 0;
        if (H5Pget_external(dcpl.get(), 0, sizeof name, name, &offset, &size) < 0) name[0] = '\0';
        hdf5Detail();
        const std::string first = name[0] ? fmt::format(" ('{}'{})", name, external > 1 ? ", ..." : "") : "";
        failInput(where, "keeps its values in {} external file{}{}: refused, Metamer reads no file an HDF5 file "
                         "names (store the values in this file)",
                  external, external == 1 ? "" : "s", first);
    }
    if (H5Pget_layout(dcpl.get()) == H5D_VIRTUAL) {
        size_t sources = 0;
        std::string first;
        if (H5Pget_virtual_count(dcpl.get(), &sources) >= 0 && sources > 0) {
            const ssize_t n = H5Pget_virtual_filename(dcpl.get(), 0, nullptr, 0);
            if (n > 0 && n < (1 << 16)) {
                std::vector<char> text(size_t(n) + 1, '\0');
                if (H5Pget_virtual_filename(dcpl.get(), 0, text.data(), text.size()) >= 0) first = text.data();
            }
        }
        hdf5Detail();
        failInput(where, "is a virtual dataset ({} source{}{}): refused, Metamer reads no file an HDF5 file names "
                         "(store the values in this file)",
                  sources, sources == 1 ? "" : "s", first.empty() ? "" : fmt::format(", the first in '{}'", first));
    }
}

// Link access that refuses to follow external links: what requireHardLink checks, should any
// call still meet one.
Handle noExternalLinks() {
    Handle dapl(H5Pcreate(H5P_DATASET_ACCESS), H5Pclose);
    if (dapl.valid())
        H5Pset_elink_cb(
            dapl.get(),
            [](const char*, const char*, const char*, const char*, unsigned*, hid_t, void*) -> herr_t { return -1; },
            nullptr);
    return dapl;
}

// Opens a dataset of the root group after the checks above.
Dataset openDataset(hid_t file, const char* name, const Where& where) {
    const Handle dapl = noExternalLinks();
    const hid_t access = orDefault(dapl);
    if (H5Lexists(file, name, access) <= 0) {
        hdf5Detail();
        failInput(where, "missing: the file has no dataset {}", name);
    }
    requireHardLink(file, name, where, access);
    Dataset d;
    d.set = Handle(H5Dopen2(file, name, access), H5Dclose);
    if (!d.set.valid()) failInput(where, "is not a readable dataset{}", withDetail(hdf5Detail()));
    requireStoredHere(d.set.get(), where);
    Handle space(H5Dget_space(d.set.get()), H5Sclose);
    Handle type(H5Dget_type(d.set.get()), H5Tclose);
    const int rank = space.valid() ? H5Sget_simple_extent_ndims(space.get()) : -1;
    if (rank < 0 || !type.valid()) failInput(where, "has an unreadable shape or type{}", withDetail(hdf5Detail()));
    d.dims.resize(size_t(rank));
    if (rank > 0 && H5Sget_simple_extent_dims(space.get(), d.dims.data(), nullptr) < 0)
        failInput(where, "has an unreadable shape{}", withDetail(hdf5Detail()));
    d.typeClass = H5Tget_class(type.get());
    return d;
}

std::string shapeOf(const std::vector<hsize_t>& dims) {
    std::string s = "[";
    for (size_t i = 0; i < dims.size(); ++i) s += fmt::format("{}{}", i ? ", " : "", dims[i]);
    return s + "]";
}

// A scalar string attribute (variable-length or fixed); nothing when absent. Present but not a
// single string: nothing with `notString` set, for the caller to refuse or ignore.
std::optional<std::string> stringAttribute(hid_t object, const char* name, bool* notString = nullptr) {
    if (notString) *notString = false;
    if (H5Aexists(object, name) <= 0) return std::nullopt;
    Handle attribute(H5Aopen(object, name, H5P_DEFAULT), H5Aclose);
    Handle type(attribute.valid() ? H5Aget_type(attribute.get()) : H5I_INVALID_HID, H5Tclose);
    Handle space(attribute.valid() ? H5Aget_space(attribute.get()) : H5I_INVALID_HID, H5Sclose);
    auto refuse = [&]() -> std::optional<std::string> {
        hdf5Detail();
        if (notString) *notString = true;
        return std::nullopt;
    };
    if (!type.valid() || !space.valid() || H5Tget_class(type.get()) != H5T_STRING ||
        H5Sget_simple_extent_npoints(space.get()) != 1)
        return refuse();
    if (H5Tis_variable_str(type.get()) > 0) {
        Handle memory(H5Tcopy(H5T_C_S1), H5Tclose);
        if (!memory.valid() || H5Tset_size(memory.get(), H5T_VARIABLE) < 0 ||
            H5Tset_cset(memory.get(), H5Tget_cset(type.get())) < 0)
            return refuse();
        char* text = nullptr;
        if (H5Aread(attribute.get(), memory.get(), &text) < 0) return refuse();
        std::string value = text ? text : "";
        H5free_memory(text);
        return value;
    }
    const size_t size = H5Tget_size(type.get());
    if (size == 0 || size > (size_t(1) << 24)) return refuse();
    std::string value(size, '\0');
    if (H5Aread(attribute.get(), type.get(), value.data()) < 0) return refuse();
    value.resize(std::min(value.find('\0'), value.size()));
    while (!value.empty() && value.back() == ' ') value.pop_back();  // space-padded strings
    return value;
}

}  // namespace

SpectralImage readHdf5Cube(const fs::path& path, const CubeHeaderCheck& check) {
    noteFileRead(path);  // metamer batch digests what a render read
    quietHdf5();
    const Where where{path.string()};
    const Where cubeWhere{path.string(), "/cube"}, wavelengthWhere{path.string(), "/wavelength_nm"};
    requireRegularFile(path, where, "HDF5 cube");

    const Handle fapl = fileAccess();
    Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, orDefault(fapl)), H5Fclose);
    if (!file.valid()) {
        const std::string detail = hdf5Detail();
        if (!hasHdf5Signature(path)) failInput(where, "not an HDF5 file (no HDF5 signature)");
        failInput(where, "truncated or damaged HDF5 file{}", withDetail(detail));
    }

    Dataset cube = openDataset(file.get(), "/cube", cubeWhere);
    if (cube.dims.size() != 3)
        failInput(cubeWhere, "has rank {} (shape {}); expected 3: [rows, columns, bands]", cube.dims.size(),
                  shapeOf(cube.dims));
    if (cube.typeClass != H5T_FLOAT)
        failInput(cubeWhere, "holds {} values; expected floating point", typeClassName(cube.typeClass));
    const hsize_t rows = cube.dims[0], columns = cube.dims[1], bands = cube.dims[2];
    const hsize_t intMax = hsize_t(std::numeric_limits<int>::max());
    if (rows == 0 || columns == 0 || bands == 0) failInput(cubeWhere, "is empty (shape {})", shapeOf(cube.dims));
    // Before allocating anything: rows·columns fits in 64 bits since each side is below 2^31.
    if (rows > intMax || columns > intMax || bands > intMax || rows * columns > kMaxValues / bands)
        failInput(cubeWhere, "shape {} holds more than 2^34 values", shapeOf(cube.dims));

    Dataset wl = openDataset(file.get(), "/wavelength_nm", wavelengthWhere);
    if (wl.dims.size() != 1)
        failInput(wavelengthWhere, "has rank {} (shape {}); expected 1: one wavelength per band", wl.dims.size(),
                  shapeOf(wl.dims));
    if (wl.typeClass != H5T_FLOAT && wl.typeClass != H5T_INTEGER)
        failInput(wavelengthWhere, "holds {} values; expected numbers", typeClassName(wl.typeClass));
    if (wl.dims[0] != bands)
        failInput(wavelengthWhere, "has {} wavelengths but /cube has {} bands (shape {})", wl.dims[0], bands,
                  shapeOf(cube.dims));
    std::vector<double> wavelengths(bands);
    if (H5Dread(wl.set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, wavelengths.data()) < 0)
        failInput(wavelengthWhere, "cannot be read (truncated or damaged file?){}", withDetail(hdf5Detail()));
    for (size_t i = 0; i < wavelengths.size(); ++i) {
        if (!std::isfinite(wavelengths[i]) || wavelengths[i] <= 0)
            failInput(wavelengthWhere, "value {} ({}) is not a wavelength in nm", i, wavelengths[i]);
        if (i > 0 && wavelengths[i] <= wavelengths[i - 1])
            failInput(wavelengthWhere, "not increasing: {} nm follows {} nm", wavelengths[i], wavelengths[i - 1]);
    }

    SpectralImage result;
    bool notString = false;
    const std::optional<std::string> quantity = stringAttribute(cube.set.get(), "quantity", &notString);
    const Where quantityWhere{path.string(), "/cube.quantity"};
    if (notString) failInput(quantityWhere, "is not a string (expected 'spectral radiance' or 'reflectance')");
    if (quantity && *quantity == "reflectance")
        result.component = SpectralComponent::Reflective;
    else if (quantity && *quantity != "spectral radiance")
        failInput(quantityWhere, "'{}' is neither 'spectral radiance' nor 'reflectance'", *quantity);

    // Our own `grid` attribute, when it agrees with the wavelengths, gives the exact grid.
    const Grid grid = gridOfWavelengths(wavelengths, stringAttribute(cube.set.get(), "grid").value_or(""),
                                        wavelengthWhere, "bands");
    if (hsize_t(grid.bands()) != bands)
        failInput(wavelengthWhere, "{} wavelengths make a grid of {} bands ({})", bands, grid.bands(), grid.str());
    if (check) check(int(columns), int(rows), int(bands));
    requireDecodableSize(columns, rows, bands, 4, 0, Where{path.string()}, "the HDF5 cube");
    result.cube = SpectralCube(int(columns), int(rows), grid);
    if (H5Dread(cube.set.get(), H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, result.cube.data.data()) < 0)
        failInput(cubeWhere, "cannot be read (truncated or damaged file?){}", withDetail(hdf5Detail()));
    return result;
}

}  // namespace metamer
