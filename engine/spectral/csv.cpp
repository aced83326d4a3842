#include "spectral/csv.h"
#include "core/file_reads.h"

#include <cerrno>
#include <map>
#include <mutex>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace metamer {

namespace {

std::string trim(const std::string& s) {
    size_t a = s.find_first_not_of(" \t\r\n");
    if (a == std::string::npos) return "";
    size_t b = s.find_last_not_of(" \t\r\n");
    return s.substr(a, b - a + 1);
}

std::vector<std::string> splitFields(const std::string& line) {
    std::vector<std::string> fields;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) fields.push_back(trim(f));
    if (!line.empty() && line.back() == ',') fields.push_back("");
    return fields;
}

bool parseNumber(const std::string& text, double& out) {
    if (text.empty()) return false;
    errno = 0;
    char* end = nullptr;
    out = std::strtod(text.c_str(), &end);
    return end == text.c_str() + text.size() && errno != ERANGE;
}

// A field as quoted in a message: a binary file read as CSV has "fields" thousands of bytes long,
// which would bury the message.
std::string shownField(const std::string& field) {
    constexpr size_t kShown = 40;
    if (field.size() <= kShown) return "'" + field + "'";
    size_t cut = kShown;
    while (cut > 0 && (static_cast<unsigned char>(field[cut]) & 0xc0) == 0x80) --cut;  // whole UTF-8 characters
    return "'" + field.substr(0, cut) + "…' (" + std::to_string(field.size()) + " characters)";
}

}  // namespace

namespace {

SpectralTable parseSpectralTable(const std::filesystem::path& path, size_t minColumns) {
    Where where{path.string(), "", 0};
    requireRegularFile(path, where, "spectrum file");
    std::ifstream in(path);
    if (!in) failInput(where, "cannot open spectrum file");
    SpectralTable t;
    std::string raw;
    int lineNo = 0;
    bool sawData = false, sawHeader = false;
    size_t width = 0;
    while (std::getline(in, raw)) {
        ++lineNo;
        where.line = lineNo;
        std::string line = trim(raw);
        if (line.empty() || line[0] == '#') continue;
        auto fields = splitFields(line);
        double w;
        if (!parseNumber(fields[0], w)) {
            if (sawData || sawHeader)
                failInput(where, "{} is not a wavelength in nm", shownField(fields[0]));
            sawHeader = true;  // first non-numeric line: the header
            t.columnNames.assign(fields.begin() + 1, fields.end());
            continue;
        }
        if (fields.size() < 2) failInput(where, "expected wavelength_nm,value; got {}", shownField(line));
        if (width == 0) {
            width = fields.size() - 1;
            if (width < minColumns)
                failInput(where, "expected at least {} value column(s), got {}", minColumns, width);
            t.columns.resize(width);
        } else if (fields.size() - 1 != width) {
            failInput(where, "expected {} value column(s) as on the first data line, got {}", width,
                      fields.size() - 1);
        }
        if (!std::isfinite(w) || w <= 0)
            failInput(where, "wavelength {} must be a positive finite number", shownField(fields[0]));
        if (!t.wavelengths_nm.empty() && !(w > t.wavelengths_nm.back()))
            failInput(where, "wavelengths must increase strictly: {} nm follows {} nm", w,
                      t.wavelengths_nm.back());
        t.wavelengths_nm.push_back(w);
        for (size_t c = 0; c < width; ++c) {
            double v;
            if (!parseNumber(fields[c + 1], v) || !std::isfinite(v))
                failInput(where, "column {}: {} is not a finite number", c + 2, shownField(fields[c + 1]));
            t.columns[c].push_back(v);
        }
        sawData = true;
    }
    where.line = 0;
    if (t.wavelengths_nm.size() < 2)
        failInput(where, "needs at least 2 data lines (wavelength_nm,value), found {}", t.wavelengths_nm.size());
    if (!t.columnNames.empty() && t.columnNames.size() != width) t.columnNames.clear();
    return t;
}

}  // namespace

// A batch (metamer batch) loads the same library tables for every job: parsed tables are kept
// for the process, each under its file's absolute path, size and modification time, so an edited
// file is read again. Errors are not kept (the next read reports them again).
SpectralTable readSpectralTable(const std::filesystem::path& path, size_t minColumns) {
    noteFileRead(path);
    struct Entry {
        uintmax_t size;
        std::filesystem::file_time_type mtime;
        SpectralTable table;
    };
    static std::mutex mutex;
    static std::map<std::pair<std::string, size_t>, Entry> cache;
    std::error_code sizeError, timeError;
    const uintmax_t size = std::filesystem::file_size(path, sizeError);
    const auto mtime = std::filesystem::last_write_time(path, timeError);
    const bool cacheable = !sizeError && !timeError && std::filesystem::is_regular_file(path, sizeError);
    std::error_code ec;
    const std::pair<std::string, size_t> key{std::filesystem::absolute(path, ec).string(), minColumns};
    if (cacheable) {
        std::lock_guard<std::mutex> lock(mutex);
        const auto it = cache.find(key);
        if (it != cache.end() && it->second.size == size && it->second.mtime == mtime) return it->second.table;
    }
    SpectralTable t = parseSpectralTable(path, minColumns);
    if (cacheable) {
        std::lock_guard<std::mutex> lock(mutex);
        cache[key] = Entry{size, mtime, t};
    }
    return t;
}

Spectrum readSpectrumCsv(const std::filesystem::path& path) {
    SpectralTable t = readSpectralTable(path, 1);
    if (t.columns.size() != 1)
        failInput(Where{path.string()}, "expected one value column (wavelength_nm,value), got {}",
                  t.columns.size());
    Spectrum s;
    s.wavelengths_nm = std::move(t.wavelengths_nm);
    s.values = std::move(t.columns[0]);
    s.source = path.string();
    return s;
}

BispectralMatrix readBispectralCsv(const std::filesystem::path& path) {
    Where where{path.string(), "", 0};
    requireRegularFile(path, where, "Donaldson matrix file");
    noteFileRead(path);
    std::ifstream in(path);
    if (!in) failInput(where, "cannot open Donaldson matrix file");
    BispectralMatrix d;
    d.source = path.string();
    std::string raw;
    int lineNo = 0;
    bool sawHeader = false;
    while (std::getline(in, raw)) {
        ++lineNo;
        where.line = lineNo;
        std::string line = trim(raw);
        if (line.empty() || line[0] == '#') continue;
        auto fields = splitFields(line);
        double x;
        if (!sawHeader) {
            // The header: a label for the λin column, then λout in nm.
            if (parseNumber(fields[0], x))
                failInput(where,
                          "expected a header row: a label (e.g. 'nm') then the emission wavelengths λout in nm; "
                          "the first field {} is a number",
                          shownField(fields[0]));
            for (size_t c = 1; c < fields.size(); ++c) {
                if (!parseNumber(fields[c], x))
                    failInput(where, "column {}: {} is not an emission wavelength in nm", c + 1, shownField(fields[c]));
                if (!std::isfinite(x) || x <= 0)
                    failInput(where, "column {}: emission wavelength {} must be a positive finite number", c + 1,
                              shownField(fields[c]));
                if (!d.out_nm.empty() && !(x > d.out_nm.back()))
                    failInput(where, "column {}: emission wavelengths must increase strictly: {:g} nm follows {:g} nm",
                              c + 1, x, d.out_nm.back());
                d.out_nm.push_back(x);
            }
            if (d.out_nm.size() < 2)
                failInput(where, "the header lists {} emission wavelength(s); a Donaldson matrix needs at least 2",
                          d.out_nm.size());
            sawHeader = true;
            continue;
        }
        if (!parseNumber(fields[0], x))
            failInput(where, "column 1: {} is not an excitation wavelength in nm", shownField(fields[0]));
        if (!std::isfinite(x) || x <= 0)
            failInput(where, "column 1: excitation wavelength {} must be a positive finite number", shownField(fields[0]));
        if (!d.in_nm.empty() && !(x > d.in_nm.back()))
            failInput(where, "excitation wavelengths must increase strictly: {:g} nm follows {:g} nm", x, d.in_nm.back());
        if (fields.size() - 1 != d.out_nm.size())
            failInput(where, "expected {} values (one per emission wavelength in the header), got {}", d.out_nm.size(),
                      fields.size() - 1);
        d.in_nm.push_back(x);
        for (size_t c = 1; c < fields.size(); ++c) {
            double v;
            if (!parseNumber(fields[c], v) || !std::isfinite(v))
                failInput(where, "column {}: {} is not a finite number", c + 1, shownField(fields[c]));
            if (v < 0)
                failInput(where, "column {}: {:g} is negative; a Donaldson matrix holds re-radiated power (≥ 0)", c + 1, v);
            d.values.push_back(v);
        }
    }
    where.line = 0;
    if (!sawHeader)
        failInput(where, "empty: expected a header row (a label, then the emission wavelengths λout in nm) and one row "
                         "per excitation wavelength λin");
    if (d.in_nm.size() < 2)
        failInput(where, "needs at least 2 excitation rows (λin,D...) below the header, found {}", d.in_nm.size());
    return d;
}

}  // namespace metamer
