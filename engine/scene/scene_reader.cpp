// The reader context shared by scene/scene_json.cpp and the material models' readers: paths a
// scene may read, spectra, Donaldson matrices, refractive indices and texture references.
// Tests: engine/scene/scene_json_test.cpp (SpectrumForms, SceneJsonBad),
// engine/scene/material_reader_transparent_test.cpp (SlabsAndTheirRefractiveIndices),
// engine/scene/scene_donaldson_test.cpp, tests/bad_inputs_test.cpp (the csv-, inline-, donaldson-
// and texture- cases), tests/textures_test.cpp.
#include "scene/scene_reader.h"

#include "core/file_reads.h"
#include "io/spectral_exr.h"
#include "spectral/csv.h"
#include "spectral/illuminant_models.h"

#include <algorithm>
#include <cctype>

namespace fs = std::filesystem;

namespace metamer {

using namespace json_read;

namespace {

// Sampled data outside the physical range is suspicious but can be legitimate (noisy
// measurements), so it is a warning.
void checkValues(const SceneSpectrum& s) {
    const auto& vals = s.spectrum.values;
    auto [lo, hi] = std::minmax_element(vals.begin(), vals.end());
    const auto& wl = s.spectrum.wavelengths_nm;
    if (*lo < 0)
        warn(s.where, fmt::format("{} spectrum '{}' is negative ({:g} at {:g} nm)", kindName(s.kind),
                                  s.spectrum.source, *lo, wl[lo - vals.begin()]));
    bool bounded = s.kind == SpectrumKind::Reflectance || s.kind == SpectrumKind::Excitation ||
                   s.kind == SpectrumKind::Transmittance;
    if (bounded && !(*hi <= kMaxRatio))
        failInput(s.where, "{} spectrum '{}' reaches {:g} at {:g} nm; a ratio above 1 is warned about and rendered up to "
                           "{:g}, no further (the GPU computes in float32)",
                  kindName(s.kind), s.spectrum.source, *hi, wl[hi - vals.begin()], kMaxRatio);
    if (s.kind == SpectrumKind::Absorbance && !(*hi <= kMaxAbsorbance))
        failInput(s.where, "{} spectrum '{}' reaches {:g} at {:g} nm; at most {:g} (an attenuation length far below a "
                           "nucleus; the GPU computes in float32)",
                  kindName(s.kind), s.spectrum.source, *hi, wl[hi - vals.begin()], kMaxAbsorbance);
    if (bounded && *hi > 1)
        warn(s.where, fmt::format("{} spectrum '{}' exceeds 1 ({:g} at {:g} nm)", kindName(s.kind),
                                  s.spectrum.source, *hi, wl[hi - vals.begin()]));
}

}  // namespace

SceneReader::SceneReader(const SpectrumLibrary& lib, const fs::path& file, bool allowOutsidePaths,
                         std::optional<Grid> renderGrid)
    : lib_(lib),
      file_(file),
      dir_(file.parent_path()),
      readable_(ReadablePaths::forScene(file, lib.root(), allowOutsidePaths)),
      renderGrid_(std::move(renderGrid)) {}

fs::path SceneReader::readableFile(const std::string& given, const Where& w, const std::string& what) const {
    fs::path path = (dir_ / given).lexically_normal();
    readable_.check(path, w, what, given);
    return path;
}

SceneSpectrum SceneReader::spectrum(const Json& v, const Where& w, SpectrumKind kind) {
    SceneSpectrum s;
    s.kind = kind;
    s.where = w;
    if (v.is_number()) {
        double x = number(v, w);
        if (kind == SpectrumKind::Emission)
            failInput(w, "an emission spectrum must be sampled data (its shape matters), not a constant");
        if (kind == SpectrumKind::Light && x < 0) failInput(w, "a light's spectrum must be ≥ 0, got {:g}", x);
        if (kind == SpectrumKind::Absorbance && x < 0) failInput(w, "an absorbance must be ≥ 0, got {:g}", x);
        if (kind == SpectrumKind::Absorbance && x > kMaxAbsorbance)
            failInput(w, "an absorbance must be at most {:g} (per metre; a dye's per mol·L⁻¹·cm⁻¹: an attenuation "
                         "length far below a nucleus), got {:g}",
                      kMaxAbsorbance, x);
        if (kind == SpectrumKind::KubelkaMunk && !(x >= 0 && x < 1e12))
            failInput(w, "a Kubelka–Munk coefficient must be within [0, 1e12) per metre, got {:g}", x);
        if ((kind == SpectrumKind::Reflectance || kind == SpectrumKind::Excitation ||
             kind == SpectrumKind::Transmittance) &&
            (x < 0 || x > 1))
            failInput(w, "a {} must be within [0, 1], got {:g}", kindName(kind), x);
        s.spectrum = Spectrum::makeConstant(x);
    } else if (v.is_string()) {
        std::string name = v.get<std::string>();
        if (name.empty()) failInput(w, "expected a spectrum name, got an empty string");
        if (endsWithCsv(name)) {
            fs::path path = readableFile(name, w, "spectrum file");
            requireRegularFile(path, w, "spectrum file");
            try {
                s.spectrum = readSpectrumCsv(path);
            } catch (const Error& e) {
                failInput(w, "{}", e.text());
            }
            s.spectrum.source = name;
        } else {
            try {
                s.spectrum = lib_.get(name, w);
            } catch (const Error& e) {
                if (e.where().file == w.file && e.where().key == w.key) throw;
                failInput(w, "library spectrum '{}': {}", name, e.text());
            }
        }
    } else if (v.is_object() && (find(v, "blackbody_k") || find(v, "daylight_cct"))) {
        // A light by its temperature (spectral/illuminant_models.h): Planck's law, or CIE daylight.
        const bool blackbody = find(v, "blackbody_k") != nullptr;
        const char* key = blackbody ? "blackbody_k" : "daylight_cct";
        checkKeys(v, w, {key}, blackbody ? "a blackbody spectrum" : "a daylight spectrum");
        if (kind != SpectrumKind::Light)
            failInput(w.child(key), "a spectrum by temperature is a light's; this is a {}", kindName(kind));
        const double kelvin = number(*find(v, key), w.child(key));
        s.spectrum = blackbody ? blackbodySpectrum(kelvin, w.child(key)) : daylightSpectrum(kelvin, lib_, w.child(key));
    } else if (v.is_object()) {
        checkKeys(v, w, {"wavelengths_nm", "values"}, "an inline spectrum");
        auto numbers = [&](const char* key) {
            Where kw = w.child(key);
            const Json& a = require(v, w, key, "an array of numbers");
            if (!a.is_array()) failInput(kw, "expected an array of numbers, got {}", describe(a));
            std::vector<double> out;
            for (size_t i = 0; i < a.size(); ++i) out.push_back(number(a[i], kw.index(i)));
            return out;
        };
        s.spectrum.wavelengths_nm = numbers("wavelengths_nm");
        s.spectrum.values = numbers("values");
        s.spectrum.source = "inline";
        s.spectrum.validate(w);
    } else {
        failInput(w,
                  "expected a spectrum (a library name, a .csv path, a number, "
                  "{{\"wavelengths_nm\": [...], \"values\": [...]}}, or for a light {{\"blackbody_k\": T}} or "
                  "{{\"daylight_cct\": T}}), got {}",
                  describe(v));
    }
    if (!s.spectrum.isConstant()) checkValues(s);
    return s;
}

// "matrix": a .csv or .exr file relative to the scene, or a library name (NAME.csv, else
// NAME.exr, under the spectra library).
SceneMatrix SceneReader::matrix(const Json& v, const Where& w) {
    if (!v.is_string())
        failInput(w, "expected a Donaldson matrix: a .csv or .exr file, or a library name; got {}", describe(v));
    std::string name = v.get<std::string>();
    if (name.empty()) failInput(w, "expected a Donaldson matrix file name, got an empty string");
    auto endsWith = [&](const char* ext) {
        std::string tail = name.size() >= 4 ? name.substr(name.size() - 4) : "";
        std::transform(tail.begin(), tail.end(), tail.begin(), [](unsigned char c) { return std::tolower(c); });
        return tail == ext;
    };
    bool exr = endsWith(".exr");
    fs::path path;
    std::error_code ec;
    if (exr || endsWith(".csv")) {
        path = readableFile(name, w, "Donaldson matrix file");
        requireRegularFile(path, w, "Donaldson matrix file");
    } else {
        fs::path base = (lib_.root() / name).lexically_normal();
        fs::path csv = base.string() + ".csv", exrPath = base.string() + ".exr";
        if (fs::is_regular_file(csv, ec)) {
            path = csv;
        } else if (fs::is_regular_file(exrPath, ec)) {
            path = exrPath;
            exr = true;
        } else {
            failInput(w, "no Donaldson matrix '{}' in the spectra library ({}): neither {}.csv nor {}.exr exists", name,
                      lib_.root().string(), name, name);
        }
        readable_.check(path, w, "Donaldson matrix file", name);
    }
    SceneMatrix m;
    m.where = w;
    try {
        if (exr) {
            BispectralExr read = readBispectralExr(path);
            m.matrix = std::move(read.matrix);
            if (read.reflectiveChannels > 0)
                warn(w, fmt::format("Donaldson matrix '{}': {} reflective T.<λ>nm channel(s) ignored; the "
                                    "material's reflectance is its 'diffuse'",
                                    name, read.reflectiveChannels));
        } else {
            m.matrix = readBispectralCsv(path);
        }
        m.matrix.validate(Where{path.string()});
    } catch (const Error& e) {
        failInput(w, "{}", e.text());
    }
    m.matrix.source = name;
    return m;
}

std::vector<double> SceneReader::numbers(const Json& v, const Where& w) {
    if (!v.is_array() || v.empty()) failInput(w, "expected a non-empty array of numbers, got {}", describe(v));
    std::vector<double> out;
    for (size_t i = 0; i < v.size(); ++i) out.push_back(number(v[i], w.index(i)));
    return out;
}

// A refractive index n(λ) (docs/scene-format.md, the slab's "ior"): a number (1 … 5), "N-BK7",
// {"sellmeier": {"B": [...], "C": [...]}}, {"cauchy": {"A": a, "B": b, "C": c}} or a table
// {"wavelengths_nm": [...], "values": [...]} (λ in µm for the formulas' coefficients, as glass
// catalogues give them), and how the scene gave it, for messages.
std::pair<RefractiveIndex, std::string> SceneReader::refractiveIndex(const Json& n, const Where& iw) {
    RefractiveIndex ior;
    std::string source;
    constexpr const char* kForms =
        "a number (1 … 5), \"N-BK7\", {\"sellmeier\": {\"B\": [...], \"C\": [...]}}, {\"cauchy\": {\"A\": a, \"B\": b, "
        "\"C\": c}} or {\"wavelengths_nm\": [...], \"values\": [...]}";
    if (n.is_number()) {
        ior.kind = RefractiveIndex::Kind::Constant;
        ior.constant = numberIn(n, iw, 1, 5, false, false);
        source = fmt::format("{:g}", ior.constant);
    } else if (n.is_string()) {
        if (n.get<std::string>() != "N-BK7") failInput(iw, "unknown glass '{}'; expected {}", n.get<std::string>(), kForms);
        ior = nbk7();
        source = "N-BK7";
    } else if (n.is_object() && find(n, "sellmeier")) {
        checkKeys(n, iw, {"sellmeier"}, "a Sellmeier index");
        const Where sw = iw.child("sellmeier");
        const Json& f = *find(n, "sellmeier");
        asObject(f, sw);
        checkKeys(f, sw, {"B", "C"}, "Sellmeier coefficients");
        ior.kind = RefractiveIndex::Kind::Sellmeier;
        ior.b = numbers(require(f, sw, "B", "the coefficients B₁ … (dimensionless)"), sw.child("B"));
        ior.c = numbers(require(f, sw, "C", "the coefficients C₁ … in µm²"), sw.child("C"));
        if (ior.b.size() != ior.c.size() || ior.b.empty())
            failInput(sw, "expected as many B as C coefficients (at least one), got {} and {}", ior.b.size(),
                      ior.c.size());
        source = "sellmeier";
    } else if (n.is_object() && find(n, "cauchy")) {
        checkKeys(n, iw, {"cauchy"}, "a Cauchy index");
        const Where cw = iw.child("cauchy");
        const Json& f = *find(n, "cauchy");
        asObject(f, cw);
        checkKeys(f, cw, {"A", "B", "C"}, "Cauchy coefficients");
        ior.kind = RefractiveIndex::Kind::Cauchy;
        ior.b = {numberIn(require(f, cw, "A", "n at infinite wavelength"), cw.child("A"), 1, 5, false, false),
                      find(f, "B") ? number(*find(f, "B"), cw.child("B")) : 0.0,
                      find(f, "C") ? number(*find(f, "C"), cw.child("C")) : 0.0};
        source = "cauchy";
    } else if (n.is_object() && find(n, "wavelengths_nm")) {
        checkKeys(n, iw, {"wavelengths_nm", "values"}, "a refractive-index table");
        ior.kind = RefractiveIndex::Kind::Table;
        ior.wavelengths_nm = numbers(require(n, iw, "wavelengths_nm", "increasing wavelengths, nm"), iw.child("wavelengths_nm"));
        ior.values = numbers(require(n, iw, "values", "n at each wavelength"), iw.child("values"));
        if (ior.values.size() != ior.wavelengths_nm.size() || ior.values.empty())
            failInput(iw, "expected as many values as wavelengths (at least one), got {} and {}",
                      ior.values.size(), ior.wavelengths_nm.size());
        for (size_t i = 1; i < ior.wavelengths_nm.size(); ++i)
            if (!(ior.wavelengths_nm[i] > ior.wavelengths_nm[i - 1]))
                failInput(iw.child("wavelengths_nm"), "wavelengths must increase ({:g} after {:g})",
                          ior.wavelengths_nm[i], ior.wavelengths_nm[i - 1]);
        source = "table";
    } else {
        failInput(iw, "expected {}, got {}", kForms, describe(n));
    }
    return {ior, source};
}

int SceneReader::textureRef(const Json& v, const Where& w, TextureRole role) {
    std::string given;
    TextureEncoding encoding = TextureEncoding::Auto;
    double scale = 1.0;
    if (v.is_string()) {
        given = v.get<std::string>();
        if (role == TextureRole::Height)
            failInput(w, "expected {{\"file\": \"...\", \"scale\": s}}: a bump map needs its scale (height in "
                         "texel widths per unit value)");
    } else if (v.is_object()) {
        if (role == TextureRole::Height)
            checkKeys(v, w, {"file", "scale"}, "a bump map");
        else if (role == TextureRole::Normal)
            checkKeys(v, w, {"file"}, "a normal map");
        else
            checkKeys(v, w, {"file", "encoding"}, "a texture");
        given = string(require(v, w, "file", "a texture file name"), w.child("file"));
        if (const Json* e = find(v, "encoding")) {
            std::string c = choice(*e, w.child("encoding"), {"auto", "srgb", "linear"});
            encoding = c == "srgb" ? TextureEncoding::Srgb : c == "linear" ? TextureEncoding::Linear : TextureEncoding::Auto;
        }
        if (role == TextureRole::Height)
            scale = numberIn(require(v, w, "scale", "the height, in texel widths, of a value step of 1"),
                             w.child("scale"), -1e6, 1e6, false, false);
    } else {
        failInput(w, "expected a texture file name or {{\"file\": ...}}, got {}", describe(v));
    }
    Where fw = v.is_object() ? w.child("file") : w;
    if (given.empty()) failInput(fw, "expected a texture file name, got an empty string");
    fs::path path = readableFile(given, fw, "texture file");
    for (size_t i = 0; i < textureKeys_.size(); ++i)
        if (textureKeys_[i].path == path && textureKeys_[i].role == role && textureKeys_[i].encoding == encoding &&
            textureKeys_[i].scale == scale)
            return int(i);
    scene_.textures.push_back(loadTexture(path, role, encoding, scale, fw, textureGrid()));
    scene_.textures.back().where = fw;
    textureKeys_.push_back({path, role, encoding, scale});
    return int(scene_.textures.size() - 1);
}

}  // namespace metamer
