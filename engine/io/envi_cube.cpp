#include "io/envi_cube.h"

#include "io/atomic_file.h"
#include "core/file_reads.h"
#include "core/memory_limits.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <limits>
#include <unistd.h>

namespace fs = std::filesystem;

namespace metamer {

namespace {

constexpr size_t kMaxHeaderBytes = size_t(16) << 20;
constexpr int kMaxSide = 65536;
constexpr int kMaxBands = 10000;
constexpr uint64_t kMaxHeaderOffset = uint64_t(1) << 48;
constexpr uint64_t kMaxValues = uint64_t(1) << 34;  // 64 GiB of float32: refused before allocating
// ENVI headers are ASCII text to most readers, so the units are spelt in ASCII here.
constexpr const char* kRadianceUnits = "W.sr^-1.m^-2.nm^-1";
constexpr int kHostByteOrder = std::endian::native == std::endian::big ? 1 : 0;

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

std::string_view trim(std::string_view s) {
    while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
    while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
    return s;
}

char lower(char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; }

std::string lowered(std::string_view s) {
    std::string out(s);
    std::transform(out.begin(), out.end(), out.begin(), lower);
    return out;
}

bool endsWithNoCase(const std::string& s, std::string_view suffix) {
    return s.size() >= suffix.size() && lowered(s.substr(s.size() - suffix.size())) == suffix;
}

// Text from the header quoted in a message: short, control characters shown as '?'.
std::string excerpt(std::string_view s) {
    constexpr size_t kMax = 60;
    std::string out(s.substr(0, kMax));
    for (char& c : out)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
    if (s.size() > kMax) out += "…";
    return out;
}

Where at(const Where& where, std::string key, int line = 0) {
    Where w{where.file, std::move(key)};
    w.line = line;
    return w;
}

}  // namespace

const char* enviInterleaveName(EnviInterleave interleave) {
    switch (interleave) {
        case EnviInterleave::Bsq: return "bsq";
        case EnviInterleave::Bil: return "bil";
        case EnviInterleave::Bip: return "bip";
    }
    return "bsq";
}

fs::path enviDataPathFor(const fs::path& headerPath) {
    fs::path data = headerPath;
    return data.replace_extension(".img");
}

// --- Writing -----------------------------------------------------------------------------------

namespace {

// A header value on one line that no reader takes for a {…} list: newlines and braces replaced.
std::string headerValue(std::string_view s) {
    std::string out(s);
    for (char& c : out) {
        if (c == '\n' || c == '\r' || c == '\0') c = ' ';
        else if (c == '{') c = '(';
        else if (c == '}') c = ')';
    }
    return std::string(trim(out));
}

// An attribute name as a header key: "metamer:scene" -> "scene", no '=' or line breaks.
std::string headerKey(std::string_view name) {
    if (name.substr(0, 8) == "metamer:") name.remove_prefix(8);
    std::string out = headerValue(name);
    std::replace(out.begin(), out.end(), '=', '_');
    return out.empty() ? "attribute" : out;
}

// "{ a, b, c}" over several lines, a few values a line, as ENVI writes long lists.
template <typename F>
std::string headerList(int count, F item) {
    std::string out = "{";
    for (int i = 0; i < count; ++i) {
        out += i % 8 == 0 ? "\n " : " ";
        out += item(i);
        if (i + 1 < count) out += ",";
    }
    return out + "}";
}

// 1-based band nearest `nm`, clamped into the grid.
int nearestBand(const Grid& grid, double nm) {
    const int bands = grid.bands();
    const double step = grid.step_nm > 0 ? grid.step_nm : 1.0;
    const double i = std::round((nm - grid.start_nm) / step);
    return int(std::clamp(i, 0.0, double(bands - 1))) + 1;
}

std::string headerText(int width, int height, const Grid& grid, const EnviWriteOptions& options) {
    const bool reflective = options.component == SpectralComponent::Reflective;
    const int bands = grid.bands();
    const char* units = reflective ? "1" : kRadianceUnits;
    std::string h = "ENVI\n";
    h += fmt::format("description = {{Metamer {} cube, {} per band}}\n",
                     reflective ? "reflectance" : "spectral radiance", units);
    h += fmt::format("samples = {}\nlines = {}\nbands = {}\nheader offset = 0\nfile type = ENVI Standard\n", width,
                     height, bands);
    h += fmt::format("data type = 4\ninterleave = {}\nbyte order = {}\n", enviInterleaveName(options.interleave),
                     kHostByteOrder);
    h += "wavelength units = Nanometers\n";
    h += "wavelength = " + headerList(bands, [&](int b) { return fmt::format("{}", grid.wavelength(b)); }) + "\n";
    h += "fwhm = " + headerList(bands, [&](int) { return fmt::format("{}", grid.step_nm); }) + "\n";
    h += "band names = " + headerList(bands, [&](int b) { return fmt::format("{} nm", grid.wavelength(b)); }) + "\n";
    h += fmt::format("default bands = {{{}, {}, {}}}\n", nearestBand(grid, 610), nearestBand(grid, 550),
                     nearestBand(grid, 465));
    h += fmt::format("metamer quantity = {}\nmetamer units = {}\n", reflective ? "reflectance" : "spectral radiance",
                     units);
    h += fmt::format("metamer grid = {}\nmetamer resampling = {}\n", grid.str(), resamplingName(grid.resampling));
    for (const auto& [name, value] : options.attributes)
        h += fmt::format("metamer {} = {}\n", headerKey(name), headerValue(value));
    return h;
}

void writeAll(int fd, const void* data, size_t bytes, uint64_t offset, const fs::path& path) {
    const char* p = static_cast<const char*>(data);
    while (bytes > 0) {
        const ssize_t n = ::pwrite(fd, p, std::min(bytes, size_t(1) << 30), off_t(offset));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) failRuntime("cannot write '{}': {}", path.string(), std::strerror(n < 0 ? errno : EIO));
        p += n;
        bytes -= size_t(n);
        offset += uint64_t(n);
    }
}

}  // namespace

struct EnviCubeWriter::Impl {
    fs::path headerPath, dataPath;
    int width = 0, height = 0, bands = 0, nextRow = 0;
    EnviInterleave interleave = EnviInterleave::Bsq;
    std::string header;
    AtomicOutput data, headerOut;  // destroyed after ~Impl has closed fd: both temporaries go
    int fd = -1;
    std::vector<float> scratch;  // one band's rows (bsq) or one line (bil)
    Impl(const fs::path& h, const fs::path& d) : headerPath(h), dataPath(d), data(d), headerOut(h) {}
    ~Impl() {
        if (fd >= 0) ::close(fd);
    }
};

EnviCubeWriter::EnviCubeWriter(const fs::path& headerPath, int width, int height, const Grid& grid,
                               const EnviWriteOptions& options) {
    if (!endsWithNoCase(headerPath.string(), ".hdr"))
        failInput(Where{headerPath.string()}, "an ENVI header's name ends in .hdr (the data goes beside it in .img)");
    impl_ = std::make_unique<Impl>(headerPath, enviDataPathFor(headerPath));
    Impl& m = *impl_;
    m.width = width;
    m.height = height;
    m.bands = grid.bands();
    m.interleave = options.interleave;
    if (width <= 0 || height <= 0 || m.bands <= 0)
        failRuntime("cannot write '{}': a {}×{} cube with {} bands", headerPath.string(), width, height, m.bands);
    m.header = headerText(width, height, grid, options);
    m.fd = ::open(m.data.tempPath().c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (m.fd < 0) failRuntime("cannot write '{}': {}", m.dataPath.string(), std::strerror(errno));
    // bsq writes each strip into every band's plane: the file has its final size from the start.
    const uint64_t bytes = uint64_t(width) * uint64_t(height) * uint64_t(m.bands) * sizeof(float);
    if (m.interleave == EnviInterleave::Bsq && ::ftruncate(m.fd, off_t(bytes)) != 0)
        failRuntime("cannot write '{}': {}", m.dataPath.string(), std::strerror(errno));
}

EnviCubeWriter::~EnviCubeWriter() = default;  // not committed: the AtomicOutputs remove the temporaries

void EnviCubeWriter::writeRows(int firstRow, int rows, const float* data) {
    Impl& m = *impl_;
    if (m.fd < 0 || firstRow != m.nextRow || rows <= 0 || firstRow > m.height - rows)
        failRuntime("cannot write '{}': rows {}..{} out of order (next is {}, height {})", m.headerPath.string(),
                    firstRow, int64_t(firstRow) + rows, m.nextRow, m.height);
    const uint64_t w = uint64_t(m.width), b = uint64_t(m.bands), h = uint64_t(m.height);
    const uint64_t y0 = uint64_t(firstRow), n = uint64_t(rows);
    switch (m.interleave) {
        case EnviInterleave::Bip:
            writeAll(m.fd, data, n * w * b * sizeof(float), y0 * w * b * sizeof(float), m.dataPath);
            break;
        case EnviInterleave::Bil:
            m.scratch.resize(b * w);
            for (uint64_t r = 0; r < n; ++r) {
                const float* row = data + r * w * b;
                for (uint64_t band = 0; band < b; ++band)
                    for (uint64_t x = 0; x < w; ++x) m.scratch[band * w + x] = row[x * b + band];
                writeAll(m.fd, m.scratch.data(), b * w * sizeof(float), (y0 + r) * b * w * sizeof(float), m.dataPath);
            }
            break;
        case EnviInterleave::Bsq:
            m.scratch.resize(n * w);
            for (uint64_t band = 0; band < b; ++band) {
                for (uint64_t i = 0; i < n * w; ++i) m.scratch[i] = data[i * b + band];
                writeAll(m.fd, m.scratch.data(), n * w * sizeof(float), (band * h + y0) * w * sizeof(float),
                         m.dataPath);
            }
            break;
    }
    m.nextRow = firstRow + rows;
}

std::vector<AtomicOutput*> EnviCubeWriter::finish() {
    Impl& m = *impl_;
    if (m.nextRow != m.height)
        failRuntime("cannot write '{}': {} of {} rows written", m.headerPath.string(), m.nextRow, m.height);
    if (m.headerOut.committed()) return {};
    if (m.fd >= 0) {
        const int fd = std::exchange(m.fd, -1);
        if (::close(fd) != 0) failRuntime("cannot write '{}': {}", m.dataPath.string(), std::strerror(errno));
    }
    {
        std::ofstream out(m.headerOut.tempPath(), std::ios::binary | std::ios::trunc);
        out << m.header;
        out.close();
        if (!out) failRuntime("cannot write '{}': the header could not be written", m.headerPath.string());
    }
    // The data first: a header that exists describes complete data.
    return {&m.data, &m.headerOut};
}

void EnviCubeWriter::commit() { commitTogether(finish()); }

void writeEnviCube(const fs::path& headerPath, const SpectralCube& cube, const EnviWriteOptions& options) {
    const size_t count = static_cast<size_t>(cube.width) * cube.height * cube.bands();
    if (cube.width <= 0 || cube.height <= 0 || cube.bands() <= 0 || cube.data.size() != count)
        failRuntime("cannot write '{}': cube is {}×{} with {} bands but holds {} values", headerPath.string(),
                    cube.width, cube.height, cube.bands(), cube.data.size());
    EnviCubeWriter writer(headerPath, cube.width, cube.height, cube.grid, options);
    writer.writeRows(0, cube.height, cube.data.data());
    writer.commit();
}

// --- The header --------------------------------------------------------------------------------

std::optional<std::string> EnviHeader::field(std::string_view key) const {
    for (auto it = fields.rbegin(); it != fields.rend(); ++it)
        if (it->first == key) return it->second;
    return std::nullopt;
}

namespace {

// The text's lines one at a time, without copying them.
class LineCursor {
public:
    explicit LineCursor(std::string_view text) : text_(text) {}
    bool next(std::string_view& line) {
        if (pos_ > text_.size()) return false;
        const size_t end = std::min(text_.find('\n', pos_), text_.size());
        line = text_.substr(pos_, end - pos_);
        pos_ = end + 1;
        ++number_;
        return true;
    }
    int number() const { return number_; }

private:
    std::string_view text_;
    size_t pos_ = 0;
    int number_ = 0;
};

// "Byte  Order" -> "byte order".
std::string normalizedKey(std::string_view key) {
    std::string out;
    for (char c : trim(key)) {
        if (isSpace(c)) {
            if (!out.empty() && out.back() != ' ') out += ' ';
        } else {
            out += lower(c);
        }
    }
    return out;
}

std::optional<long long> wholeNumber(std::string_view s) {
    s = trim(s);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    long long v = 0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
    return v;
}

std::optional<double> realNumber(std::string_view s) {
    s = trim(s);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    double v = 0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
    return v;
}

const char* dataTypeName(long long code) {
    switch (code) {
        case 1: return "8-bit unsigned integer";
        case 2: return "16-bit signed integer";
        case 3: return "32-bit signed integer";
        case 4: return "float32";
        case 5: return "float64";
        case 6: return "complex float32";
        case 9: return "complex float64";
        case 12: return "16-bit unsigned integer";
        case 13: return "32-bit unsigned integer";
        case 14: return "64-bit signed integer";
        case 15: return "64-bit unsigned integer";
        default: return "not an ENVI data type";
    }
}

// nm per unit of `units`, or nothing for a unit we do not read.
std::optional<double> nanometresPer(std::string_view units) {
    const std::string u = lowered(trim(units));
    if (u == "nanometers" || u == "nanometer" || u == "nanometres" || u == "nanometre" || u == "nm") return 1.0;
    if (u == "micrometers" || u == "micrometer" || u == "micrometres" || u == "micrometre" || u == "microns" ||
        u == "micron" || u == "um" || u == "µm")
        return 1000.0;
    return std::nullopt;
}

}  // namespace

EnviHeader parseEnviHeader(const std::string& text, const Where& where) {
    if (text.size() > kMaxHeaderBytes)
        failInput(where, "{} bytes: an ENVI header over 16 MiB is refused", text.size());
    if (text.size() >= 2 && (text.substr(0, 2) == "\xFF\xFE" || text.substr(0, 2) == "\xFE\xFF"))
        failInput(where, "is UTF-16 text (it starts with a UTF-16 byte-order mark); an ENVI header is ASCII: save it as "
                         "UTF-8");
    if (const size_t nul = text.find('\0'); nul != std::string::npos)
        failInput(at(where, "", int(std::count(text.begin(), text.begin() + std::ptrdiff_t(nul), '\n')) + 1),
                  "a NUL byte: not a text header");

    EnviHeader h;
    std::string_view body(text);
    if (body.substr(0, 3) == "\xEF\xBB\xBF") body.remove_prefix(3);  // a UTF-8 byte-order mark
    LineCursor lines(body);
    std::string_view line;
    bool first = true;
    while (lines.next(line)) {
        line = trim(line);
        if (first) {
            if (line.empty()) continue;
            if (line != "ENVI")
                failInput(at(where, "", lines.number()), "not an ENVI header: the first line is '{}', not 'ENVI'",
                          excerpt(line));
            first = false;
            continue;
        }
        if (line.empty() || line.front() == ';') continue;  // ';' starts a comment line
        const size_t eq = line.find('=');
        if (eq == std::string_view::npos)
            failInput(at(where, "", lines.number()), "expected 'key = value', found '{}'", excerpt(line));
        std::string key = normalizedKey(line.substr(0, eq));
        if (key.empty()) failInput(at(where, "", lines.number()), "'= {}' has no key", excerpt(line.substr(eq + 1)));
        std::string_view value = trim(line.substr(eq + 1));
        if (value.empty() || value.front() != '{') {
            h.fields.emplace_back(std::move(key), std::string(value));
            continue;
        }
        // A {…} value runs to the first '}', across lines if need be.
        const int opened = lines.number();
        std::string collected;
        std::string_view rest = value.substr(1);
        for (;;) {
            const size_t close = rest.find('}');
            if (close != std::string_view::npos) {
                collected += rest.substr(0, close);
                if (std::string_view after = trim(rest.substr(close + 1)); !after.empty())
                    failInput(at(where, key, lines.number()), "'{}' after the closing '}}'", excerpt(after));
                break;
            }
            collected += rest;
            collected += '\n';
            if (!lines.next(rest))
                failInput(at(where, key, opened), "the '{{' opened on line {} is never closed", opened);
            rest = trim(rest);
        }
        h.fields.emplace_back(std::move(key), std::string(trim(collected)));
    }
    if (first) failInput(where, "empty: not an ENVI header (no 'ENVI' line)");

    auto required = [&](const char* key) {
        std::optional<std::string> v = h.field(key);
        if (!v) failInput(at(where, key), "missing: an ENVI header of a spectral cube needs '{} = …'", key);
        return *v;
    };
    auto integer = [&](const char* key, const std::string& value, long long lo, long long hi) {
        const std::optional<long long> v = wholeNumber(value);
        if (!v || *v < lo || *v > hi)
            failInput(at(where, key), "'{}' is not a whole number from {} to {}", excerpt(value), lo, hi);
        return *v;
    };

    h.samples = int(integer("samples", required("samples"), 1, kMaxSide));
    h.lines = int(integer("lines", required("lines"), 1, kMaxSide));
    h.bands = int(integer("bands", required("bands"), 1, kMaxBands));
    if (std::optional<std::string> offset = h.field("header offset"))
        h.headerOffset = size_t(integer("header offset", *offset, 0, (long long)kMaxHeaderOffset));
    if (std::optional<std::string> type = h.field("file type"); type && lowered(*type).rfind("envi standard", 0) != 0)
        failInput(at(where, "file type"), "'{}' is not supported: only ENVI Standard images", excerpt(*type));

    const std::string dataType = required("data type");
    const std::optional<long long> code = wholeNumber(dataType);
    if (!code) failInput(at(where, "data type"), "'{}' is not an ENVI data type code", excerpt(dataType));
    if (*code != 4 && *code != 5)
        failInput(at(where, "data type"), "{} ({}) is not supported: only 4 (float32) and 5 (float64)", *code,
                  dataTypeName(*code));
    h.dataType = int(*code);

    const std::string interleave = lowered(trim(required("interleave")));
    if (interleave == "bsq") h.interleave = EnviInterleave::Bsq;
    else if (interleave == "bil") h.interleave = EnviInterleave::Bil;
    else if (interleave == "bip") h.interleave = EnviInterleave::Bip;
    else failInput(at(where, "interleave"), "'{}' is not bsq, bil or bip", excerpt(interleave));

    h.byteOrder = int(integer("byte order", required("byte order"), 0, 1));

    h.wavelengthUnits = required("wavelength units");
    const std::optional<double> toNm = nanometresPer(h.wavelengthUnits);
    if (!toNm)
        failInput(at(where, "wavelength units"), "'{}' is not a unit metamer reads: Nanometers or Micrometers",
                  excerpt(h.wavelengthUnits));
    // One finite number per band, checked by count before any is parsed (the list may be huge).
    auto list = [&](const char* key, const std::string& value) {
        const size_t count = value.empty() ? 0 : size_t(std::count(value.begin(), value.end(), ',')) + 1;
        if (count != size_t(h.bands))
            failInput(at(where, key), "{} values for {} bands", count, h.bands);
        std::vector<double> out;
        out.reserve(count);
        std::string_view rest(value);
        for (size_t i = 0; i < count; ++i) {
            const size_t comma = std::min(rest.find(','), rest.size());
            const std::optional<double> v = realNumber(rest.substr(0, comma));
            if (!v || !std::isfinite(*v * *toNm))
                failInput(at(where, key), "value {} ('{}') is not a finite number", i + 1,
                          excerpt(trim(rest.substr(0, comma))));
            out.push_back(*v * *toNm);
            rest.remove_prefix(std::min(comma + 1, rest.size()));
        }
        return out;
    };
    h.wavelengths_nm = list("wavelength", required("wavelength"));
    if (std::optional<std::string> fwhm = h.field("fwhm")) h.fwhm_nm = list("fwhm", *fwhm);
    return h;
}

// --- Reading -----------------------------------------------------------------------------------

namespace {

// Found, and a regular file (not a folder, FIFO or device), checked before anything opens it.
void requireRegularFile(const fs::path& path) { metamer::requireRegularFile(path, Where{path.string()}, "ENVI cube"); }

bool isRegularFile(const fs::path& path) {
    std::error_code ec;
    return fs::is_regular_file(fs::status(path, ec));
}

// "ENVI" at the start, also after a UTF-8 or UTF-16 byte-order mark (a header saved by an
// editor as UTF-16 is still meant as one: parseEnviHeader then says what is wrong with it).
bool startsWithEnvi(const fs::path& path) {
    if (!isRegularFile(path)) return false;
    std::ifstream in(path, std::ios::binary);
    char head[10] = {};
    in.read(head, sizeof head);
    const std::string_view h(head, size_t(in.gcount()));
    // (Split literals: a hex escape would swallow the letter after it.)
    return h.substr(0, 4) == "ENVI" || h.substr(0, 7) == "\xEF\xBB\xBF" "ENVI" ||
           h == std::string_view("\xFF\xFE" "E\0N\0V\0I\0", 10) || h == std::string_view("\xFE\xFF" "\0E\0N\0V\0I", 10);
}

std::string names(const std::vector<fs::path>& paths) {
    std::string s;
    for (size_t i = 0; i < paths.size(); ++i) s += (i ? ", " : "") + paths[i].filename().string();
    return s;
}

// The data file beside a header: <stem>.img, then the header's name without .hdr (x.img.hdr),
// then the other extensions in use.
fs::path dataFileFor(const fs::path& header) {
    std::vector<fs::path> candidates;
    auto with = [&](const char* extension) { return fs::path(header).replace_extension(extension); };
    candidates.push_back(with(".img"));
    if (endsWithNoCase(header.string(), ".hdr")) candidates.push_back(with(""));
    for (const char* e : {".dat", ".raw", ".bsq", ".bil", ".bip", ".IMG", ".DAT", ".RAW"}) candidates.push_back(with(e));
    for (const fs::path& c : candidates)
        if (c != header && isRegularFile(c)) return c;
    // Something of that name that is not a file (a folder, a FIFO): say so rather than "not found".
    for (const fs::path& c : candidates) {
        std::error_code ec;
        if (c != header && fs::exists(fs::status(c, ec))) requireRegularFile(c);
    }
    failInput(Where{header.string()}, "no ENVI data file beside the header (looked for {})", names(candidates));
}

fs::path headerFileFor(const fs::path& data) {
    const std::vector<fs::path> candidates = {fs::path(data).replace_extension(".hdr"), fs::path(data.string() + ".hdr"),
                                              fs::path(data).replace_extension(".HDR")};
    for (const fs::path& c : candidates)
        if (isRegularFile(c)) return c;
    failInput(Where{data.string()}, "no ENVI header beside the data file (looked for {})", names(candidates));
}

std::string readHeaderText(const fs::path& header) {
    requireRegularFile(header);
    std::error_code ec;
    const uintmax_t size = fs::file_size(header, ec);
    if (ec) failInput(Where{header.string()}, "cannot be read: {}", ec.message());
    if (size > kMaxHeaderBytes) failInput(Where{header.string()}, "{} bytes: an ENVI header over 16 MiB is refused", size);
    std::ifstream in(header, std::ios::binary);
    std::string text(size_t(size), '\0');
    if (!in.read(text.data(), std::streamsize(size))) failInput(Where{header.string()}, "cannot be read");
    return text;
}

// One value of the data file, in host order, as float (float64 beyond float's range becomes ±Inf).
float decode(const unsigned char* p, int dataType, bool swap) {
    if (dataType == 4) {
        uint32_t u;
        std::memcpy(&u, p, 4);
        if (swap) u = __builtin_bswap32(u);
        return std::bit_cast<float>(u);
    }
    uint64_t u;
    std::memcpy(&u, p, 8);
    if (swap) u = __builtin_bswap64(u);
    const double d = std::bit_cast<double>(u);
    constexpr double kMax = std::numeric_limits<float>::max();
    if (d > kMax) return std::numeric_limits<float>::infinity();  // a plain cast would be undefined
    if (d < -kMax) return -std::numeric_limits<float>::infinity();
    return float(d);
}

// Where the data file's values go in the pixel-interleaved cube, one value after the other.
struct Scatter {
    size_t samples, lines, bands;
    EnviInterleave order;
    size_t k = 0, x = 0, y = 0, band = 0;
    size_t index() const { return order == EnviInterleave::Bip ? k : (y * samples + x) * bands + band; }
    void step() {
        ++k;
        if (order == EnviInterleave::Bip || ++x < samples) return;
        x = 0;
        if (order == EnviInterleave::Bil) {  // [line][band][sample]
            if (++band == bands) band = 0, ++y;
        } else if (++y == lines) {  // bsq: [band][line][sample]
            y = 0, ++band;
        }
    }
};

}  // namespace

SpectralImage readEnviCube(const fs::path& path, const CubeHeaderCheck& check) {
    requireRegularFile(path);
    const bool givenHeader = startsWithEnvi(path) || endsWithNoCase(path.string(), ".hdr");
    const fs::path header = givenHeader ? path : headerFileFor(path);
    const EnviHeader h = parseEnviHeader(readHeaderText(header), Where{header.string()});
    const fs::path data = givenHeader ? dataFileFor(header) : path;
    // Both files decide the result (metamer batch digests what a render read).
    noteFileRead(header);
    noteFileRead(data);
    requireRegularFile(data);

    const Where headerWhere{header.string()}, dataWhere{data.string()};
    const uint64_t values = uint64_t(h.samples) * uint64_t(h.lines) * uint64_t(h.bands);
    if (values > kMaxValues)
        failInput(headerWhere, "{}×{}×{} is more than 2^34 values", h.samples, h.lines, h.bands);
    const uint64_t expected = h.headerOffset + values * h.bytesPerValue();
    std::error_code ec;
    const uintmax_t actual = fs::file_size(data, ec);
    if (ec) failInput(dataWhere, "cannot be read: {}", ec.message());
    if (actual != expected)
        failInput(dataWhere, "is {} bytes; the header ({}) describes {} bytes: {} + {}×{}×{} values of {} bytes ({})",
                  actual, header.filename().string(), expected, h.headerOffset, h.samples, h.lines, h.bands,
                  h.bytesPerValue(), actual < expected ? "truncated" : "too long");

    if (h.wavelengths_nm.front() <= 0)
        failInput(Where{header.string(), "wavelength"}, "{} nm is not a wavelength", h.wavelengths_nm.front());
    for (size_t i = 1; i < h.wavelengths_nm.size(); ++i)
        if (h.wavelengths_nm[i] <= h.wavelengths_nm[i - 1])
            failInput(Where{header.string(), "wavelength"}, "not increasing: {} nm follows {} nm", h.wavelengths_nm[i],
                      h.wavelengths_nm[i - 1]);
    SpectralImage result;
    if (std::optional<std::string> q = h.field("metamer quantity")) {
        if (*q == "reflectance") result.component = SpectralComponent::Reflective;
        else if (*q != "spectral radiance")
            failInput(Where{header.string(), "metamer quantity"}, "'{}' is neither 'spectral radiance' nor 'reflectance'",
                      excerpt(*q));
    }
    const Grid grid = gridOfWavelengths(h.wavelengths_nm, h.field("metamer grid").value_or(""),
                                        Where{header.string(), "wavelength"}, "bands");
    if (grid.bands() != h.bands)
        failInput(Where{header.string(), "wavelength"}, "{} wavelengths make a grid of {} bands ({})", h.bands,
                  grid.bands(), grid.str());

    if (check) check(h.samples, h.lines, h.bands);
    requireDecodableSize(uint64_t(h.samples), uint64_t(h.lines), uint64_t(h.bands), 4, 0, Where{header.string()},
                         "the ENVI cube");
    result.cube = SpectralCube(h.samples, h.lines, grid);
    // In blocks of a million values: a line of a bip file alone may hold 655 million.
    constexpr uint64_t kBlock = uint64_t(1) << 20;
    const size_t bytes = h.bytesPerValue();
    const bool swap = h.byteOrder != kHostByteOrder;
    std::vector<unsigned char> buffer(size_t(std::min(values, kBlock)) * bytes);
    std::ifstream in(data, std::ios::binary);
    in.seekg(std::streamoff(h.headerOffset));
    Scatter to{size_t(h.samples), size_t(h.lines), size_t(h.bands), h.interleave};
    float* cube = result.cube.data.data();
    for (uint64_t done = 0; done < values;) {
        const size_t n = size_t(std::min(values - done, kBlock));
        if (!in.read(reinterpret_cast<char*>(buffer.data()), std::streamsize(n * bytes)))
            failRuntime("cannot read '{}': it ended early or could not be read", data.string());
        for (size_t i = 0; i < n; ++i, to.step()) cube[to.index()] = decode(buffer.data() + i * bytes, h.dataType, swap);
        done += n;
    }
    return result;
}

bool isEnviHeaderFile(const fs::path& path) { return startsWithEnvi(path); }

}  // namespace metamer
