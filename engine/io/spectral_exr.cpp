#include "io/spectral_exr.h"

#include "core/error.h"
#include "core/memory_limits.h"
#include "io/atomic_file.h"
#include "io/exr_file.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <memory>
#include <numeric>
#include <optional>

namespace fs = std::filesystem;

namespace metamer {

namespace {

constexpr float kHalfMax = 65504.0f;
constexpr double kGridTolerance_nm = 1e-4;
constexpr const char* kQuantity = "spectral radiance per band (docs/physics.md), W·sr⁻¹·m⁻²·nm⁻¹";
constexpr const char* kReflectanceQuantity = "reflectance factor per band, relative (1: a perfect white diffuser)";

// A parsed S0.<λ><unit> / T.<λ><unit> channel.
struct BandChannel {
    double wavelength_nm;
    int index;
};

// Parses the quantity after the component prefix: a number with ',' or '.' as decimal separator
// and an optional exponent, then an SI prefix and "m" or "Hz". Returns nm, or nothing when the
// text is not exactly that (e.g. a bispectral "500nm.600nm").
std::optional<double> parseWavelength(std::string_view s) {
    size_t i = 0;
    auto digits = [&] {
        size_t b = i;
        while (i < s.size() && s[i] >= '0' && s[i] <= '9') ++i;
        return i > b;
    };
    bool intPart = digits();
    bool fracPart = false;
    if (i < s.size() && (s[i] == ',' || s[i] == '.')) {
        ++i;
        fracPart = digits();
    }
    if (!intPart && !fracPart) return std::nullopt;
    if (i + 1 < s.size() && (s[i] == 'e' || s[i] == 'E')) {
        size_t save = i++;
        if (s[i] == '+' || s[i] == '-') ++i;
        if (!digits()) i = save;  // "E" was an SI prefix (exa), not an exponent
    }
    std::string number(s.substr(0, i));
    std::replace(number.begin(), number.end(), ',', '.');
    double v = 0;
    auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), v);
    if (ec != std::errc() || end != number.data() + number.size()) return std::nullopt;

    std::string_view unit = s.substr(i);
    bool hertz = unit.size() >= 2 && unit.substr(unit.size() - 2) == "Hz";
    bool metre = !hertz && !unit.empty() && unit.back() == 'm';
    if (!hertz && !metre) return std::nullopt;
    std::string_view prefix = unit.substr(0, unit.size() - (hertz ? 2 : 1));
    // Powers of ten, so that nm (the usual case) converts without any rounding.
    static const std::pair<std::string_view, int> prefixes[] = {
        {"Y", 24}, {"Z", 21}, {"E", 18}, {"P", 15},  {"T", 12},  {"G", 9},   {"M", 6},
        {"k", 3},  {"h", 2},  {"da", 1}, {"", 0},    {"d", -1},  {"c", -2},  {"m", -3},
        {"u", -6}, {"n", -9}, {"p", -12}, {"f", -15}, {"a", -18}, {"z", -21}, {"y", -24}};
    auto it = std::find_if(std::begin(prefixes), std::end(prefixes),
                           [&](const auto& p) { return p.first == prefix; });
    if (it == std::end(prefixes)) return std::nullopt;
    if (hertz) {
        double frequency = v * std::pow(10.0, it->second);
        if (!(frequency > 0)) return std::nullopt;
        return 299792458.0 / frequency * 1e9;
    }
    int toNm = it->second + 9;
    return toNm >= 0 ? v * std::pow(10.0, toNm) : v / std::pow(10.0, -toNm);
}

// "S0.552,5nm" -> 552.5 when the name has the given component prefix ("S0" or "T").
std::optional<double> bandOf(const std::string& name, std::string_view component) {
    if (name.size() <= component.size() || name.compare(0, component.size(), component) != 0)
        return std::nullopt;
    std::string_view rest(name);
    rest.remove_prefix(component.size());
    if (rest.front() != '.') return std::nullopt;  // "S01..." is not S0; Fichet allows extra dots
    while (!rest.empty() && rest.front() == '.') rest.remove_prefix(1);
    return parseWavelength(rest);
}

}  // namespace

Grid gridOfWavelengths(const std::vector<double>& wl, const std::string& gridText, const Where& where,
                       const std::string& what) {
    const size_t n = wl.size();
    if (n == 0) failInput(where, "no {}", what);
    for (size_t i = 1; i < n; ++i)
        if (wl[i] - wl[i - 1] < kGridTolerance_nm) failInput(where, "two {} at {} nm", what, wl[i]);
    // Prefer our own grid text (metamer:grid) when it agrees with the wavelengths: exact values.
    if (!gridText.empty()) {
        try {
            Grid g = Grid::parse(gridText, where);
            bool agrees = g.bands() == static_cast<int>(n);
            for (size_t i = 0; agrees && i < n; ++i)
                agrees = std::fabs(g.wavelength(static_cast<int>(i)) - wl[i]) <= kGridTolerance_nm;
            if (agrees) return g;
        } catch (const Error&) {
            // Not ours or out of the render limits: fall back to the wavelengths.
        }
    }
    Grid g;
    g.start_nm = wl.front();
    g.end_nm = wl.back();
    if (n == 1) {
        g.step_nm = 1.0;  // one band: the step is not recorded in the wavelengths
        return g;
    }
    double step = (g.end_nm - g.start_nm) / static_cast<double>(n - 1);
    // Channel names carry 6 decimals; snap the step to them when that is within rounding.
    double snapped = std::round(step * 1e6) / 1e6;
    g.step_nm = std::fabs(snapped - step) * static_cast<double>(n - 1) < 1e-6 ? snapped : step;
    for (size_t i = 1; i < n; ++i) {
        if (std::fabs(g.start_nm + static_cast<double>(i) * g.step_nm - wl[i]) > kGridTolerance_nm)
            failInput(where, "{} are not on a uniform grid: {} nm and {} nm are {} nm apart, the mean step is {} nm",
                      what, wl[i - 1], wl[i], wl[i] - wl[i - 1], g.step_nm);
    }
    return g;
}

std::string spectralChannelName(double wavelength_nm, SpectralComponent component) {
    const std::string prefix = component == SpectralComponent::Reflective ? "T" : "S0";
    std::string n = fmt::format("{:.6f}nm", wavelength_nm);
    std::replace(n.begin(), n.end(), '.', ',');
    return prefix + "." + n;  // the separator after the component stays a dot
}

struct SpectralExrWriter::Impl {
    fs::path path;
    int width = 0, height = 0, bands = 0, nextRow = 0;
    bool half = false;
    AtomicOutput out;
    std::unique_ptr<ExrWriter> writer;
    ExrWriteReport report;
    std::vector<float> clamped;  // half: the strip with finite overflow clamped to ±65504
    std::vector<float> clampedPreview;  // the same for the preview's rows
    bool preview = false;
    explicit Impl(const fs::path& p) : path(p), out(p) {}
};

SpectralExrWriter::SpectralExrWriter(const fs::path& path, int width, int height, const Grid& grid,
                                     const ExrWriteOptions& options)
    : impl_(std::make_unique<Impl>(path)) {
    Impl& m = *impl_;
    m.width = width;
    m.height = height;
    m.bands = grid.bands();
    m.half = options.half;
    if (width <= 0 || height <= 0 || m.bands <= 0)
        failRuntime("cannot write '{}': a {}×{} cube with {} bands", path.string(), width, height, m.bands);
    if (!knownExrCompression(options.compression))
        failInput(Where{"", "compression"}, "unknown OpenEXR compression '{}' ({}; zip, zips take :1 to :9, dwaa, "
                  "dwab a :level)", options.compression, exrCompressionNames());
    std::vector<std::string> channels;
    const bool reflective = options.component == SpectralComponent::Reflective;
    for (int b = 0; b < m.bands; ++b) channels.push_back(spectralChannelName(grid.wavelength(b), options.component));
    StringAttributes a = {{"spectralLayoutVersion", "1.0"}};
    if (!reflective) a.push_back({"emissiveUnits", "W.m^-2.sr^-1"});
    a.insert(a.end(), {{"metamer:grid", grid.str()},
                       {"metamer:quantity", reflective ? kReflectanceQuantity : kQuantity},
                       {"metamer:resampling", resamplingName(grid.resampling)},
                       {"Software", "metamer"}});
    a.insert(a.end(), options.extraAttributes.begin(), options.extraAttributes.end());
    ExrWriterExtras extras;
    if (options.preview) {
        m.preview = true;
        extras.extraChannels = previewChannelNames();
        extras.chromaticities = options.preview;
        a.push_back({"metamer:rgb", "R, G, B: the display image's linear RGB (its primaries in chromaticities; "
                                    "white = 1), A = 1; docs/io.md, \"Preview channels\""});
    }
    m.writer = std::make_unique<ExrWriter>(m.out.tempPath(), width, height, channels, m.half, options.compression, a,
                                           extras);
}

const std::vector<std::string>& previewChannelNames() {
    static const std::vector<std::string> names{"R", "G", "B", "A"};
    return names;
}

SpectralExrWriter::~SpectralExrWriter() = default;  // not committed: AtomicOutput removes the temporary file

void SpectralExrWriter::writeRows(int firstRow, int rows, const float* data) { writeRows(firstRow, rows, data, nullptr); }

void SpectralExrWriter::writeRows(int firstRow, int rows, const float* data, const float* preview) {
    Impl& m = *impl_;
    if (firstRow != m.nextRow || rows <= 0 || firstRow + rows > m.height)
        failRuntime("cannot write '{}': rows {}..{} out of order (next is {}, height {})", m.path.string(), firstRow,
                    firstRow + rows, m.nextRow, m.height);
    if (m.preview && !preview)
        failRuntime("cannot write '{}': rows {}..{} come without their preview (R, G, B, A)", m.path.string(),
                    firstRow, firstRow + rows);
    const size_t count = size_t(m.width) * rows * m.bands;
    const float* pixels = data;
    if (m.half) {
        // Half: clamp finite overflow ourselves (a plain conversion would turn it into ±Inf).
        m.clamped.resize(count);
        for (size_t i = 0; i < count; ++i) {
            float v = data[i];
            if (!std::isfinite(v)) {
                ++m.report.nonFinite;
            } else if (std::fabs(v) > kHalfMax) {
                ++m.report.clampedToHalfMax;
                v = std::copysign(kHalfMax, v);
            }
            m.clamped[i] = v;
        }
        pixels = m.clamped.data();
    } else {
        for (size_t i = 0; i < count; ++i) m.report.nonFinite += !std::isfinite(data[i]);
    }
    const float* previewPixels = m.preview ? preview : nullptr;
    if (previewPixels && m.half) {
        // The preview is for looking at: its overflow is clamped as the bands' is, and not counted.
        m.clampedPreview.assign(preview, preview + size_t(m.width) * rows * 4);
        for (float& v : m.clampedPreview)
            if (std::isfinite(v) && std::fabs(v) > kHalfMax) v = std::copysign(kHalfMax, v);
        previewPixels = m.clampedPreview.data();
    }
    m.out.naming([&] { m.writer->writeRows(firstRow, rows, pixels, previewPixels); });
    m.nextRow = firstRow + rows;
}

std::vector<AtomicOutput*> SpectralExrWriter::finish() {
    Impl& m = *impl_;
    if (m.nextRow != m.height)
        failRuntime("cannot write '{}': {} of {} rows written", m.path.string(), m.nextRow, m.height);
    m.out.naming([&] { m.writer->close(); });
    return {&m.out};
}

const ExrWriteReport& SpectralExrWriter::report() const { return impl_->report; }

ExrWriteReport SpectralExrWriter::commit() {
    commitTogether(finish());
    return impl_->report;
}

ExrWriteReport writeSpectralExr(const fs::path& path, const SpectralCube& cube,
                                const ExrWriteOptions& options) {
    const size_t count = static_cast<size_t>(cube.width) * cube.height * cube.bands();
    if (cube.width <= 0 || cube.height <= 0 || cube.bands() <= 0 || cube.data.size() != count)
        failRuntime("cannot write '{}': cube is {}×{} with {} bands but holds {} values", path.string(),
                    cube.width, cube.height, cube.bands(), cube.data.size());
    SpectralExrWriter writer(path, cube.width, cube.height, cube.grid, options);
    writer.writeRows(0, cube.height, cube.data.data());
    return writer.commit();
}

bool hasSpectralChannels(const std::vector<std::string>& channelNames) {
    for (const auto& name : channelNames)
        if (name.rfind("S0.", 0) == 0 || name.rfind("T.", 0) == 0) return true;
    return false;
}

namespace {

std::string attributeOf(const ExrHeader& h, const std::string& name) {
    for (const auto& [k, v] : h.attributes)
        if (k == name) return v;
    return "";
}

std::string someChannels(const std::vector<std::string>& channels) {
    std::string names;
    for (size_t c = 0; c < channels.size() && c < 8; ++c) names += (c ? ", " : "") + channels[c];
    if (channels.size() > 8) names += ", ...";
    return names;
}

}  // namespace

SpectralExrImage readSpectralExrImage(const fs::path& path, const CubeHeaderCheck& check) {
    Where where{path.string()};
    const ExrHeader h = readExrHeader(path, where);
    std::vector<BandChannel> emissive, reflective;
    for (int c = 0; c < int(h.channels.size()); ++c) {
        const std::string& name = h.channels[size_t(c)];
        if (auto w = bandOf(name, "S0")) emissive.push_back({*w, c});
        else if (auto t = bandOf(name, "T")) reflective.push_back({*t, c});
    }
    SpectralExrImage result;
    std::vector<BandChannel>* chosen = &emissive;
    if (emissive.empty()) {
        chosen = &reflective;
        result.component = SpectralComponent::Reflective;
    }
    if (chosen->empty())
        failInput(where, "no spectral channels (expected S0.<λ>nm or T.<λ>nm; found {})", someChannels(h.channels));
    auto& bands = *chosen;
    // EXR stores channels alphabetically ("1000,0nm" before "300,0nm"): sort by wavelength.
    std::stable_sort(bands.begin(), bands.end(), [](const BandChannel& a, const BandChannel& b) {
        return a.wavelength_nm < b.wavelength_nm;
    });
    std::vector<double> wavelengths;
    for (const auto& b : bands) wavelengths.push_back(b.wavelength_nm);
    Grid grid = gridOfWavelengths(wavelengths, attributeOf(h, "metamer:grid"), where);
    // OpenEXR reads the channels straight into the cube's band order.
    std::vector<std::string> names;
    for (const auto& b : bands) names.push_back(h.channels[size_t(b.index)]);
    if (check) check(h.width, h.height, int(names.size()));
    requireDecodableSize(uint64_t(std::max(0, h.width)), uint64_t(std::max(0, h.height)), names.size(), 4, 0, where,
                         "the spectral OpenEXR image");
    result.cube = SpectralCube(h.width, h.height, grid);
    result.cube.data = readExrChannels(path, names, where);
    return result;
}

SpectralCube readSpectralExr(const fs::path& path) {
    SpectralExrImage image = readSpectralExrImage(path);
    if (image.component != SpectralComponent::Emissive)
        failInput(Where{path.string()},
                  "holds reflectance (T.<λ>nm channels), not spectral radiance (S0.<λ>nm)");
    return std::move(image.cube);
}

namespace {

// "T.400nm.500nm" (any number of dots after T and between the two quantities, ',' or '.' as the
// decimal separator) -> (400, 500). Splits at each '.' in turn: exactly one split gives two
// wavelengths, since a decimal point cannot end a quantity (it has no unit yet).
std::optional<std::pair<double, double>> bispectralPairOf(const std::string& name) {
    if (name.size() < 2 || name[0] != 'T' || name[1] != '.') return std::nullopt;
    std::string_view rest(name);
    rest.remove_prefix(1);
    while (!rest.empty() && rest.front() == '.') rest.remove_prefix(1);
    for (size_t p = rest.find('.'); p != std::string_view::npos; p = rest.find('.', p + 1)) {
        auto in = parseWavelength(rest.substr(0, p));
        if (!in) continue;
        std::string_view second = rest.substr(p + 1);
        while (!second.empty() && second.front() == '.') second.remove_prefix(1);
        if (auto out = parseWavelength(second)) return std::make_pair(*in, *out);
    }
    return std::nullopt;
}

// The distinct values of `v` (sorted), merging those closer than the channels' 1e-4 nm tolerance.
std::vector<double> axisOf(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    std::vector<double> axis;
    for (double x : v)
        if (axis.empty() || x - axis.back() >= kGridTolerance_nm) axis.push_back(x);
    return axis;
}

size_t indexOn(const std::vector<double>& axis, double x) {
    auto it = std::lower_bound(axis.begin(), axis.end(), x - kGridTolerance_nm);
    return size_t(it - axis.begin());
}

}  // namespace

BispectralExr readBispectralExr(const fs::path& path) {
    Where where{path.string()};
    const ExrHeader h = readExrHeader(path, where);
    if (h.width != 1 || h.height != 1)
        failInput(where,
                  "is a {}×{} image; a Donaldson matrix file must be 1×1 (one material: bispectral textures are not "
                  "supported)",
                  h.width, h.height);
    const std::vector<std::string>& channels = h.channels;

    BispectralExr result;
    struct PairChannel {
        double in, out;
        int index;
    };
    std::vector<PairChannel> pairs;
    for (int c = 0; c < int(channels.size()); ++c) {
        const std::string& name = channels[size_t(c)];
        if (auto p = bispectralPairOf(name))
            pairs.push_back({p->first, p->second, c});
        else if (bandOf(name, "T"))
            ++result.reflectiveChannels;
        else
            ++result.otherChannels;
    }
    if (pairs.empty())
        failInput(where, "no bispectral channels (expected T.<λin>nm.<λout>nm; found {})",
                  channels.empty() ? std::string("none") : someChannels(channels));
    const std::vector<float> pixel = readExrChannels(path, channels, where);

    BispectralMatrix& d = result.matrix;
    d.source = path.string();
    std::vector<double> ins, outs;
    for (const auto& p : pairs) {
        ins.push_back(p.in);
        outs.push_back(p.out);
    }
    d.in_nm = axisOf(ins);
    d.out_nm = axisOf(outs);
    if (d.in_nm.size() < 2 || d.out_nm.size() < 2)
        failInput(where,
                  "its bispectral channels name {} excitation and {} emission wavelength(s); a Donaldson matrix needs "
                  "at least 2 of each",
                  d.in_nm.size(), d.out_nm.size());
    d.values.assign(d.in_nm.size() * d.out_nm.size(), 0.0);
    std::vector<int> owner(d.values.size(), -1);
    for (const auto& p : pairs) {
        const std::string& name = channels[size_t(p.index)];
        const size_t k = indexOn(d.in_nm, p.in) * d.out_nm.size() + indexOn(d.out_nm, p.out);
        if (owner[k] >= 0)
            failInput(where, "channels '{}' and '{}' both hold D({:g} nm, {:g} nm)", channels[size_t(owner[k])], name,
                      p.in, p.out);
        owner[k] = p.index;
        const double v = pixel[size_t(p.index)];
        if (!std::isfinite(v)) failInput(where, "channel '{}': {} is not a finite number", name, v);
        if (v < 0)
            failInput(where, "channel '{}': {:g} is negative; a Donaldson matrix holds re-radiated power (≥ 0)", name, v);
        d.values[k] = v;
    }
    return result;
}

}  // namespace metamer
