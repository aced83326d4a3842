#include "sensor/sensor_spec.h"

#include "core/error.h"
#include "core/file_reads.h"
#include "scene/json_values.h"
#include "spectral/csv.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cctype>
#include <cmath>

namespace metamer {

namespace fs = std::filesystem;
using namespace json_read;

namespace {

// A name ending in .csv is a file beside the sensor file; anything else a library table.
fs::path tablePath(const std::string& name, const fs::path& dir, const SpectrumLibrary& library) {
    if (endsWithCsv(name)) return (dir / name).lexically_normal();
    return library.root() / (name + ".csv");
}

// A quantity per wavelength (a lens's, a transmittance): a number (the same at every λ) or {"wavelengths_nm": [...],
// "values": [...]} (linear between the points, the end values beyond), each value in [lo, hi].
Spectrum perWavelength(const Json& v, const Where& w, double lo, double hi, const char* unit) {
    Spectrum s;
    if (v.is_number()) return Spectrum::makeConstant(numberIn(v, w, lo, hi, false, false, unit));
    if (!v.is_object())
        failInput(w, "expected a number{} or {{\"wavelengths_nm\": [...], \"values\": [...]}}; got {}", unit,
                  describe(v));
    checkKeys(v, w, {"wavelengths_nm", "values"}, "a value per wavelength");
    const Json& nm = require(v, w, "wavelengths_nm", "increasing wavelengths, nm");
    const Json& values = require(v, w, "values", "a value per wavelength");
    if (!nm.is_array() || !values.is_array() || nm.size() != values.size() || nm.size() < 2)
        failInput(w, "expected as many values as wavelengths (at least two)");
    for (size_t i = 0; i < nm.size(); ++i) {
        s.wavelengths_nm.push_back(number(nm[i], w.child("wavelengths_nm").index(i)));
        s.values.push_back(numberIn(values[i], w.child("values").index(i), lo, hi, false, false, unit));
    }
    s.source = "inline";
    s.validate(w);
    return s;
}

// T(λ): a number, a table name or {"wavelengths_nm": [...], "values": [...]}; 0 … 1.
Spectrum transmittance(const Json& v, const Where& w, const fs::path& dir, const SpectrumLibrary& library,
                       std::vector<fs::path>& inputs) {
    Spectrum s;
    if (v.is_number()) {
        s = Spectrum::makeConstant(numberIn(v, w, 0, 1, false, false));
    } else if (v.is_string()) {
        const std::string name = string(v, w);
        if (endsWithCsv(name)) {
            const fs::path p = tablePath(name, dir, library);
            requireRegularFile(p, w, "transmittance file");
            inputs.push_back(p);
            try {
                s = readSpectrumCsv(p);
            } catch (const Error& e) {
                failInput(w, "{}", e.text());
            }
        } else {
            s = library.get(name, w);
        }
    } else if (v.is_object()) {
        s = perWavelength(v, w, 0, 1, "");
    } else {
        failInput(w, "expected a transmittance: a number 0 … 1, a spectrum name or {{\"wavelengths_nm\": [...], "
                     "\"values\": [...]}}; got {}",
                  describe(v));
    }
    if (!s.isConstant())
        for (size_t i = 0; i < s.values.size(); ++i)
            if (!(s.values[i] >= 0.0 && s.values[i] <= 1.0))
                failInput(w, "the transmittance is {:g} at {:g} nm; expected 0 … 1", s.values[i], s.wavelengths_nm[i]);
    return s;
}

// The CFA's tile from "RGGB"-like letters: each letter the channel whose name starts with it.
LensSpec readLens(const Json& v, const Where& w) {
    asObject(v, w);
    checkKeys(v, w, {"diffraction", "defocus_um", "longitudinal_ca_um", "lateral_ca", "pixel_aperture", "olpf_um",
                     "zernike_waves"},
              "the lens");
    LensSpec lens;
    auto flag = [&](const char* key, bool& out) {
        if (const Json* b = find(v, key)) {
            if (!b->is_boolean()) failInput(w.child(key), "expected true or false; got {}", describe(*b));
            out = b->get<bool>();
        }
    };
    flag("diffraction", lens.diffraction);
    flag("pixel_aperture", lens.pixelAperture);
    // A millimetre of defocus is a blur wider than any sensor's pixels at f/1000; a 10 % lateral
    // CA a lens no one would use: beyond them a number is a mistake.
    if (const Json* d = find(v, "defocus_um")) lens.defocus_um = numberIn(*d, w.child("defocus_um"), -1e4, 1e4, false, false, " µm");
    if (const Json* c = find(v, "longitudinal_ca_um")) lens.focusShift_um = perWavelength(*c, w.child("longitudinal_ca_um"), -1e4, 1e4, " µm");
    if (const Json* c = find(v, "lateral_ca")) lens.lateralCa = perWavelength(*c, w.child("lateral_ca"), -0.1, 0.1, "");
    if (const Json* o = find(v, "olpf_um")) lens.olpf_um = numberIn(*o, w.child("olpf_um"), 0, 100, false, false, " µm");
    // {"4": 0.05, "7": {"wavelengths_nm": [...], "values": [...]}}: Noll's index → waves (RMS).
    if (const Json* z = find(v, "zernike_waves")) {
        const Where zw = w.child("zernike_waves");
        asObject(*z, zw);
        for (const auto& [key, value] : z->items()) {
            int j = 0;
            const auto [end, ec] = std::from_chars(key.data(), key.data() + key.size(), j);
            if (ec != std::errc() || end != key.data() + key.size() || j < 1 || j > 36)
                failInput(zw.child(key), "expected Noll's index of a Zernike term, 1 … 36, as the key");
            if (lens.zernike.size() < size_t(j)) lens.zernike.resize(size_t(j), Spectrum::makeConstant(0.0));
            // Ten waves RMS is a blur no Zernike sum describes well on a grid that holds the pupil.
            lens.zernike[size_t(j - 1)] = perWavelength(value, zw.child(key), -10, 10, " waves");
        }
        if (!lens.diffraction && !lens.zernike.empty())
            failInput(w.child("diffraction"), "a wavefront (zernike_waves) is the aperture's: it needs diffraction");
    }
    return lens;
}

ProcessorSpec readProcessor(const Json& v, const Where& w, const SpectrumLibrary& library) {
    asObject(v, w);
    checkKeys(v, w,
              {"white_balance", "patch", "illuminant", "demosaic", "colour_correction", "adaptation", "exposure",
               "display", "bits"},
              "the processor");
    ProcessorSpec p;
    if (const Json* b = find(v, "white_balance"))
        p.whiteBalance = parseWhiteBalance(choice(*b, w.child("white_balance"), {"illuminant", "grey-world", "patch"}),
                                           w.child("white_balance"));
    if (const Json* r = find(v, "patch")) {
        if (p.whiteBalance != WhiteBalance::Patch)
            failInput(w.child("patch"), "a patch is for \"white_balance\": \"patch\"; the white balance is {}",
                      whiteBalanceName(p.whiteBalance));
        const glm::dvec4 rect = vector<4>(*r, w.child("patch"));
        for (int i = 0; i < 4; ++i) p.patch[size_t(i)] = patchCoordinate(rect[i], w.child("patch").index(size_t(i)));
    } else if (p.whiteBalance == WhiteBalance::Patch) {
        failInput(w.child("patch"), "the patch white balance needs \"patch\": [x, y, width, height] in pixels, a "
                  "neutral area of the frame");
    }
    if (const Json* i = find(v, "illuminant")) {
        p.illuminant = string(*i, w.child("illuminant"));
        library.get(p.illuminant, w.child("illuminant"));  // an unknown name is an error here, with a suggestion
    }
    if (const Json* d = find(v, "demosaic"))
        p.demosaic = parseDemosaicMethod(choice(*d, w.child("demosaic"), {"bilinear", "malvar2004"}), w.child("demosaic"));
    if (const Json* c = find(v, "colour_correction"))
        p.correction = parseCorrectionForm(choice(*c, w.child("colour_correction"), {"linear", "root-polynomial"}),
                                           w.child("colour_correction"));
    if (const Json* a = find(v, "adaptation")) p.adaptation = parseAdaptation(string(*a, w.child("adaptation")), w.child("adaptation"));
    if (const Json* e = find(v, "exposure"))
        p.exposure = numberIn(*e, w.child("exposure"), kMinProcessorExposure, kMaxProcessorExposure, false, false);
    if (const Json* d = find(v, "display")) p.display = choice(*d, w.child("display"), {"srgb", "crt"});
    if (const Json* b = find(v, "bits")) p.bits = displayBits(integerIn(*b, w.child("bits"), 8, 16), w.child("bits"));
    return p;
}

std::vector<std::vector<int>> cfaFromLetters(const std::string& letters, const std::vector<std::string>& channels,
                                             const Where& w) {
    std::vector<int> tile;
    for (char c : letters) {
        int found = -1;
        for (size_t i = 0; i < channels.size(); ++i)
            if (!channels[i].empty() && std::tolower(channels[i][0]) == std::tolower(c)) {
                if (found >= 0)
                    failInput(w, "'{}': letter '{}' names two channels ({} and {}); give the pattern as rows of channel "
                                 "names",
                              letters, c, channels[size_t(found)], channels[i]);
                found = int(i);
            }
        if (found < 0)
            failInput(w, "'{}': no channel starts with '{}' (the channels are {})", letters, c, join(channels));
        tile.push_back(found);
    }
    return {{tile[0], tile[1]}, {tile[2], tile[3]}};
}

}  // namespace

bool namesSensorFile(const std::string& given) {
    const fs::path asFile(given);
    return asFile.extension() == ".json" || asFile.has_parent_path();
}

fs::path sensorFile(const std::string& given, const SpectrumLibrary& library) {
    if (namesSensorFile(given)) return given;
    const fs::path inLibrary = library.root() / "sensors" / (given + ".json");
    if (fs::exists(inLibrary)) return inLibrary;
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(library.root() / "sensors", ec))
        if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
    std::sort(names.begin(), names.end());
    failInput(Where{"--sensor"}, "'{}' is neither a .json file nor a library sensor (the library has {})", given,
              names.empty() ? std::string("none") : join(names));
}

SensorSpec readSensor(const fs::path& file, const SpectrumLibrary& library) {
    SensorSpec s;
    s.file = file;
    s.inputs.push_back(file);
    const Json doc = parseJson(readWholeFile(file, Where{file.string()}, "sensor file"), file.string());
    const Where root{file.string()};
    asObject(doc, root);
    const fs::path dir = file.parent_path();
    checkKeys(doc, root,
              {"description", "optics", "pixel", "quantum_efficiency", "cfa", "exposure_s", "auto_exposure_full_well",
               "dark_current_e_per_s", "full_well_e", "conversion_gain_dn_per_e", "read_noise_e", "prnu", "dsnu_e",
               "black_level_dn", "adc_bits", "fpn_seed", "processor"},
              "a sensor");
    if (const Json* d = find(doc, "description")) s.description = string(*d, root.child("description"));

    s.lensTransmittance = Spectrum::makeConstant(1.0);
    if (const Json* o = find(doc, "optics")) {
        const Where ow = root.child("optics");
        asObject(*o, ow);
        checkKeys(*o, ow, {"f_number", "transmittance", "magnification", "cos4_focal_length_mm", "lens"}, "the optics");
        if (const Json* l = find(*o, "lens")) s.lens = readLens(*l, ow.child("lens"));
        if (const Json* n = find(*o, "f_number")) s.fNumber = numberIn(*n, ow.child("f_number"), 0.5, 1000, false, false);
        if (const Json* t = find(*o, "transmittance"))
            s.lensTransmittance = transmittance(*t, ow.child("transmittance"), dir, library, s.inputs);
        if (const Json* m = find(*o, "magnification"))
            s.magnification = numberIn(*m, ow.child("magnification"), 0, 100, false, false);
        if (const Json* f = find(*o, "cos4_focal_length_mm")) {
            s.cos4 = true;
            // No lens is shorter than 0.1 mm: below it the field angle's tangent overflows at the
            // sensor's corners (10⁻³⁰⁰ mm made every pixel NaN, blamed on the cube).
            s.focalLength_mm = numberIn(*f, ow.child("cos4_focal_length_mm"), 0.1, 1e5, false, false, " mm");
        }
    }

    const Where pw = root.child("pixel");
    const Json& pixel = require(doc, root, "pixel", "{\"pitch_um\": p, \"fill_factor\": f}");
    asObject(pixel, pw);
    checkKeys(pixel, pw, {"pitch_um", "fill_factor"}, "the pixel");
    s.pitch_um = numberIn(require(pixel, pw, "pitch_um", "the pixel pitch in µm"), pw.child("pitch_um"), 0, 1000, true,
                          false, " µm");
    if (const Json* f = find(pixel, "fill_factor")) s.fillFactor = numberIn(*f, pw.child("fill_factor"), 0, 1, true, false);

    const Where qw = root.child("quantum_efficiency");
    const Json& qe = require(doc, root, "quantum_efficiency",
                             "{\"table\": a library table or a .csv file of one column per channel, \"peak\": the "
                             "largest QE}");
    asObject(qe, qw);
    checkKeys(qe, qw, {"table", "peak", "includes_fill_factor"}, "the quantum efficiency");
    // EMVA 1288's QE is the pixel's: photons on its whole area, fill factor and microlenses
    // included. A photodiode's own QE (false) is multiplied by the fill factor.
    if (const Json* f = find(qe, "includes_fill_factor")) {
        if (!f->is_boolean())
            failInput(qw.child("includes_fill_factor"), "expected true (EMVA 1288: the QE per pixel area, the default) "
                      "or false (the photodiode's QE, multiplied by pixel.fill_factor); got {}", jsonTypeName(*f));
        s.qeIncludesFillFactor = f->get<bool>();
    }
    const std::string table = string(require(qe, qw, "table", "a table of one column per channel"), qw.child("table"));
    const double peak = numberIn(require(qe, qw, "peak", "the largest quantum efficiency of any channel, 0 … 1"),
                                 qw.child("peak"), 0, 1, true, false);
    const fs::path tp = tablePath(table, dir, library);
    requireRegularFile(tp, qw.child("table"), "quantum-efficiency table");
    s.inputs.push_back(tp);
    SpectralTable t;
    try {
        t = readSpectralTable(tp, 1);
    } catch (const Error& e) {
        failInput(qw.child("table"), "{}", e.text());
    }
    double largest = 0.0;
    for (const auto& column : t.columns)
        for (double v : column) largest = std::max(largest, v);
    if (!(largest > 0.0)) failInput(qw.child("table"), "table '{}' holds no positive value", table);
    for (size_t c = 0; c < t.columns.size(); ++c) {
        Spectrum q;
        q.wavelengths_nm = t.wavelengths_nm;
        for (double v : t.columns[c]) q.values.push_back(std::max(0.0, v) * peak / largest);
        s.channels.push_back(c < t.columnNames.size() && !t.columnNames[c].empty() ? t.columnNames[c]
                                                                                   : fmt::format("c{}", c));
        q.source = table + ":" + s.channels.back();
        s.quantumEfficiency.push_back(std::move(q));
    }
    s.qeSource = fmt::format("{} scaled to a peak of {:g}", table, peak);

    const Where cw = root.child("cfa");
    const Json& cfa = require(doc, root, "cfa", "\"RGGB\", \"BGGR\", \"GRBG\", \"GBRG\", \"mono\" or rows of channel names");
    if (cfa.is_string()) {
        s.cfaName = string(cfa, cw);
        if (s.cfaName == "mono") {
            if (s.channels.size() != 1)
                failInput(cw, "a monochrome sensor has one channel; the quantum-efficiency table has {} ({})",
                          s.channels.size(), join(s.channels));
            s.cfa = {{0}};
        } else {
            const std::string name = choice(cfa, cw, {"RGGB", "BGGR", "GRBG", "GBRG", "mono"});
            s.cfa = cfaFromLetters(name, s.channels, cw);
        }
    } else if (cfa.is_array() && !cfa.empty() && cfa.size() <= 16) {
        s.cfaName = "custom";
        for (size_t r = 0; r < cfa.size(); ++r) {
            const Where rw = cw.index(r);
            if (!cfa[r].is_array() || cfa[r].empty() || cfa[r].size() != cfa[0].size() || cfa[r].size() > 16)
                failInput(rw, "expected a row of 1 … 16 channel names, as long as the first row");
            std::vector<int> row;
            for (size_t c = 0; c < cfa[r].size(); ++c) {
                const std::string name = string(cfa[r][c], rw.index(c));
                const auto it = std::find(s.channels.begin(), s.channels.end(), name);
                if (it == s.channels.end())
                    failInput(rw.index(c), "unknown channel '{}'; the quantum-efficiency table's are {}", name,
                              join(s.channels));
                row.push_back(int(it - s.channels.begin()));
            }
            s.cfa.push_back(std::move(row));
        }
    } else {
        failInput(cw, "expected \"RGGB\", \"BGGR\", \"GRBG\", \"GBRG\", \"mono\" or 1 … 16 rows of channel names; got {}",
                  describe(cfa));
    }

    const Json& exposure = require(doc, root, "exposure_s", "an exposure time in seconds, or \"auto\"");
    if (exposure.is_string()) {
        if (string(exposure, root.child("exposure_s")) != "auto")
            failInput(root.child("exposure_s"), "expected an exposure time in seconds or \"auto\"");
    } else {
        s.exposure_s = numberIn(exposure, root.child("exposure_s"), 0, 1e6, true, false, " s");
    }
    if (const Json* a = find(doc, "auto_exposure_full_well"))
        s.autoExposureFullWellFraction = numberIn(*a, root.child("auto_exposure_full_well"), 0, 1, true, false);
    auto optionalIn = [&](const char* key, double lo, double hi, double fallback) {
        const Json* v = find(doc, key);
        return v ? numberIn(*v, root.child(key), lo, hi, false, false) : fallback;
    };
    s.darkCurrent_e_per_s = optionalIn("dark_current_e_per_s", 0, 1e9, 0.0);
    s.fullWell_e = numberIn(require(doc, root, "full_well_e", "the full-well capacity in electrons"),
                            root.child("full_well_e"), 1, 1e9, false, false, " e⁻");
    s.gain_dn_per_e = numberIn(require(doc, root, "conversion_gain_dn_per_e", "K, digital numbers per electron"),
                               root.child("conversion_gain_dn_per_e"), 0, 1e6, true, false, " DN/e⁻");
    s.readNoise_e = optionalIn("read_noise_e", 0, 1e6, 0.0);
    s.prnu = optionalIn("prnu", 0, 1, 0.0);
    s.dsnu_e = optionalIn("dsnu_e", 0, 1e6, 0.0);
    s.adcBits = find(doc, "adc_bits") ? integerIn(*find(doc, "adc_bits"), root.child("adc_bits"), 1, 16) : 12;
    s.blackLevel_dn = optionalIn("black_level_dn", 0, double(s.whiteLevel()), 0.0);
    if (const Json* f = find(doc, "fpn_seed")) {
        const double seed = numberIn(*f, root.child("fpn_seed"), 0, 9007199254740992.0, false, false);
        if (std::floor(seed) != seed) failInput(root.child("fpn_seed"), "expected a whole number, got {:g}", seed);
        s.fpnSeed = uint64_t(seed);
    }
    if (const Json* p = find(doc, "processor")) s.processor = readProcessor(*p, root.child("processor"), library);
    return s;
}

}  // namespace metamer
