// The spectra library in spectra/: every file loads, the names scenes rely on exist, and the data
// and models have the properties documented in spectra/README.md.
#include "spectral/csv.h"
#include "spectral/resampling.h"
#include "spectral/library.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

fs::path libraryRoot() { return fs::path(METAMER_SOURCE_DIR) / "spectra"; }

const SpectrumLibrary& library() {
    static const SpectrumLibrary lib(libraryRoot());
    return lib;
}

const Spectrum& get(const std::string& name) { return library().get(name, Where{"library_test"}); }

bool isObserver(const std::string& name) { return name.rfind("observers/", 0) == 0; }

const std::vector<std::string> kColorChecker = {
    "dark_skin", "light_skin",   "blue_sky",    "foliage",   "blue_flower", "bluish_green",
    "orange",    "purplish_blue", "moderate_red", "purple",   "yellow_green", "orange_yellow",
    "blue",      "green",        "red",         "yellow",    "magenta",     "cyan",
    "white_9_5", "neutral_8",    "neutral_6_5", "neutral_5", "neutral_3_5", "black_2"};

const std::vector<std::string> kDyes = {"brightener", "orange_dye", "pink_dye"};

std::vector<std::string> requiredNames() {
    std::vector<std::string> names = {"illuminants/A",          "illuminants/D50",
                                      "illuminants/D65",        "illuminants/E",
                                      "illuminants/blacklight", "metals/gold",
                                      "metals/silver",          "metals/copper",
                                      "metals/aluminium",       "observers/cie1931_2deg",
                                      "observers/cie1964_10deg"};
    for (int i = 1; i <= 12; ++i) names.push_back("illuminants/FL" + std::to_string(i));
    for (const auto& c : kColorChecker) names.push_back("colorchecker/" + c);
    for (const auto& d : kDyes)
        for (const char* part : {"_ex", "_em", "_base"}) names.push_back("fluorescent/" + d + part);
    return names;
}

double peakWavelength(const Spectrum& s) {
    auto it = std::max_element(s.values.begin(), s.values.end());
    return s.wavelengths_nm[it - s.values.begin()];
}

double maxValue(const Spectrum& s) { return *std::max_element(s.values.begin(), s.values.end()); }
double minValue(const Spectrum& s) { return *std::min_element(s.values.begin(), s.values.end()); }

// Σ v·Δλ of a resampled spectrum.
double bandSum(const std::vector<double>& v, double step) {
    double sum = 0.0;
    for (double x : v) sum += x * step;
    return sum;
}

}  // namespace

TEST(Library, ContainsEveryRequiredName) {
    std::vector<std::string> names = library().names();
    for (const auto& n : requiredNames()) {
        EXPECT_TRUE(library().contains(n)) << n;
        EXPECT_TRUE(std::binary_search(names.begin(), names.end(), n)) << n;
    }
    size_t checkers = std::count_if(names.begin(), names.end(), [](const std::string& n) {
        return n.rfind("colorchecker/", 0) == 0;
    });
    EXPECT_EQ(checkers, 24u);
}

TEST(Library, EveryFileLoadsAndValidates) {
    ASSERT_FALSE(library().names().empty());
    for (const auto& name : library().names()) {
        SCOPED_TRACE(name);
        fs::path path = libraryRoot() / (name + ".csv");
        if (isObserver(name)) {
            SpectralTable t;
            ASSERT_NO_THROW(t = readSpectralTable(path, 3));
            EXPECT_EQ(t.columnNames, (std::vector<std::string>{"x_bar", "y_bar", "z_bar"}));
            for (const auto& col : t.columns)
                for (double v : col) EXPECT_GE(v, 0.0);
            continue;
        }
        // Other tables (camera sensitivities, film data): several columns, all finite.
        SpectralTable table;
        ASSERT_NO_THROW(table = readSpectralTable(path, 1));
        if (table.columns.size() > 1) continue;
        const Spectrum* s = nullptr;
        ASSERT_NO_THROW(s = &get(name));
        EXPECT_NO_THROW(s->validate(Where{name}));
        EXPECT_EQ(s->source, name);
        EXPECT_GE(minValue(*s), 0.0);  // nothing in the library is negative
        // Every single-spectrum file has a header naming its one column ("value" for spectra).
        EXPECT_EQ(table.columnNames.size(), 1u);
    }
}

// Issue 49, item 3: the measured reflectances (spectra/generate_reflectances.py), every one listed
// in the index with its source's label, and every listed one in the library.
TEST(Library, TheReflectanceSetsAreAllThereAndIndexed) {
    std::ifstream index(libraryRoot() / "reflectances" / "index.tsv");
    ASSERT_TRUE(index) << "spectra/reflectances/index.tsv";
    std::string line;
    std::getline(index, line);
    EXPECT_EQ(line, "set\tname\tlibrary_name\tsource_label\tstart_nm\tend_nm\tstep_nm");
    std::map<std::string, int> perSet;
    std::set<std::string> listed;
    while (std::getline(index, line)) {
        std::vector<std::string> fields;
        for (size_t start = 0;;) {
            const size_t tab = line.find('\t', start);
            fields.push_back(line.substr(start, tab == std::string::npos ? std::string::npos : tab - start));
            if (tab == std::string::npos) break;
            start = tab + 1;
        }
        ASSERT_EQ(fields.size(), 7u) << line;
        ++perSet[fields[0]];
        EXPECT_TRUE(library().contains(fields[2])) << fields[2];
        EXPECT_EQ(fields[2], "reflectances/" + fields[0] + "/" + fields[1]);
        listed.insert(fields[2]);
        const Spectrum& s = get(fields[2]);
        EXPECT_EQ(s.minWavelength(), std::stod(fields[4])) << fields[2];
        EXPECT_EQ(s.maxWavelength(), std::stod(fields[5])) << fields[2];
        EXPECT_LE(maxValue(s), 1.0) << fields[2];  // reflectances, not a fluorescent sample's radiance factor
    }
    EXPECT_EQ(perSet, (std::map<std::string, int>{{"aces_training", 185}, {"babelcolor_average", 24}, {"cie_2017_ces", 99},
                                                  {"cie_tcs", 15}, {"nist_cqs_vs", 15}, {"pmc", 30}}));
    for (const std::string& name : library().names())
        if (name.rfind("reflectances/", 0) == 0) EXPECT_TRUE(listed.count(name)) << name << " is not in the index";
    EXPECT_EQ(listed.size(), 368u);
}

// Issue 49, item 2: the CIE's LED, FL3 and HP lamp series (spectra/generate_illuminants.py), for
// scene draws that choose a light from a folder; each covers 380–780 nm, and each kind shows its
// physics: a phosphor LED's blue pump at 440–460 nm, a violet-pumped one's below 420 nm, a
// high-pressure sodium lamp's output in its broadened D lines (560–620 nm).
TEST(Library, TheCieLampSeriesAreThere) {
    std::map<std::string, int> perSeries;
    for (const std::string& name : library().names())
        for (const char* series : {"illuminants/cie_led/", "illuminants/cie_fl3/", "illuminants/cie_hp/"})
            if (name.rfind(series, 0) == 0) {
                ++perSeries[series];
                const Spectrum& s = get(name);
                EXPECT_EQ(s.minWavelength(), 380.0) << name;
                EXPECT_EQ(s.maxWavelength(), 780.0) << name;
                EXPECT_GT(maxValue(s), 0.0) << name;
            }
    EXPECT_EQ(perSeries, (std::map<std::string, int>{
                             {"illuminants/cie_fl3/", 15}, {"illuminants/cie_hp/", 5}, {"illuminants/cie_led/", 9}}));
    auto peakIn = [](const Spectrum& s, double lo, double hi) {  // the wavelength of the largest value in [lo, hi]
        double best = lo, value = -1;
        for (double nm = lo; nm <= hi; nm += 5)
            if (s.at(nm) > value) value = s.at(nm), best = nm;
        return best;
    };
    for (const char* b : {"B1", "B2", "B3", "B4", "B5"}) {
        const double pump = peakIn(get(std::string("illuminants/cie_led/") + b), 380, 500);
        EXPECT_GE(pump, 440.0) << b;
        EXPECT_LE(pump, 460.0) << b;
    }
    for (const char* v : {"V1", "V2"}) EXPECT_LT(peakIn(get(std::string("illuminants/cie_led/") + v), 380, 500), 420.0) << v;
    const Spectrum& sodium = get("illuminants/cie_hp/HP1");
    double inLines = 0, all = 0;
    for (double nm = 380; nm <= 780; nm += 5) {
        all += sodium.at(nm);
        if (nm >= 560 && nm <= 620) inLines += sodium.at(nm);
    }
    EXPECT_GT(inLines / all, 0.5);
}

TEST(Library, D65AndAAre100At560) {
    EXPECT_NEAR(get("illuminants/D65").at(560), 100.0, 1e-6);
    EXPECT_NEAR(get("illuminants/D50").at(560), 100.0, 1e-6);
    EXPECT_NEAR(get("illuminants/A").at(560), 100.0, 1e-6);
    // A comes from the Planck formula at 1 nm; D65 is the CIE table at 5 nm.
    EXPECT_EQ(get("illuminants/A").minWavelength(), 300.0);
    EXPECT_EQ(get("illuminants/A").maxWavelength(), 830.0);
    EXPECT_NEAR(get("illuminants/A").at(300), 0.930483, 1e-6);
    EXPECT_NEAR(get("illuminants/D65").at(460), 117.812, 1e-9);
}

TEST(Library, EqualEnergyCoversEveryAllowedGrid) {
    const Spectrum& e = get("illuminants/E");
    EXPECT_LE(e.minWavelength(), Grid::kMinWavelength);
    EXPECT_GE(e.maxWavelength(), Grid::kMaxWavelength);
    Grid g{200, 2500, 50};
    for (double v : resample(e, g)) EXPECT_DOUBLE_EQ(v, 100.0);
}

TEST(Library, FluorescentIlluminantsAreCieRange) {
    for (int i = 1; i <= 12; ++i) {
        const Spectrum& s = get("illuminants/FL" + std::to_string(i));
        EXPECT_EQ(s.minWavelength(), 380.0);
        EXPECT_EQ(s.maxWavelength(), 780.0);
        EXPECT_EQ(s.values.size(), 81u);
    }
    EXPECT_DOUBLE_EQ(get("illuminants/FL1").at(560), 14.33);  // the CIE's own normalization
}

TEST(Library, Cie1931ObserverHasKnownValues) {
    SpectralTable t = readSpectralTable(libraryRoot() / "observers/cie1931_2deg.csv", 3);
    ASSERT_EQ(t.wavelengths_nm.front(), 360.0);
    ASSERT_EQ(t.wavelengths_nm.back(), 830.0);
    ASSERT_EQ(t.wavelengths_nm.size(), 471u);
    const auto& y = t.columns[1];
    size_t i555 = 555 - 360;
    ASSERT_EQ(t.wavelengths_nm[i555], 555.0);
    EXPECT_NEAR(y[i555], 1.0, 1e-3);
    double sum = 0.0;
    for (double v : y) sum += v * 1.0;  // step 1 nm
    EXPECT_NEAR(sum, 106.857, 0.01);    // colour-science 0.4.7: 106.856917
}

TEST(Library, Cie1964ObserverHasKnownValues) {
    SpectralTable t = readSpectralTable(libraryRoot() / "observers/cie1964_10deg.csv", 3);
    ASSERT_EQ(t.wavelengths_nm.size(), 471u);
    const auto& y = t.columns[1];
    double sum = 0.0;
    for (double v : y) sum += v;
    EXPECT_NEAR(sum, 116.662, 0.01);  // colour-science 0.4.7: 116.661877
    auto peak = std::max_element(y.begin(), y.end()) - y.begin();
    EXPECT_NEAR(t.wavelengths_nm[peak], 557.0, 2.0);
}

TEST(Library, ColorCheckerValuesAreReflectanceFactors) {
    for (const auto& c : kColorChecker) {
        SCOPED_TRACE(c);
        const Spectrum& s = get("colorchecker/" + c);
        EXPECT_EQ(s.minWavelength(), 380.0);
        EXPECT_EQ(s.maxWavelength(), 780.0);
        for (double v : s.values) {
            EXPECT_GE(v, 0.0);
            EXPECT_LE(v, 1.0);
        }
    }
    // The neutral row gets darker from white to black.
    double prev = 2.0;
    for (const char* n : {"white_9_5", "neutral_8", "neutral_6_5", "neutral_5", "neutral_3_5", "black_2"}) {
        double v = get(std::string("colorchecker/") + n).at(550);
        EXPECT_LT(v, prev) << n;
        prev = v;
    }
}

TEST(Library, DyeAbsorptancePlusBaseAtMostOne) {
    for (const auto& d : kDyes) {
        SCOPED_TRACE(d);
        const Spectrum& ex = get("fluorescent/" + d + "_ex");
        const Spectrum& base = get("fluorescent/" + d + "_base");
        ASSERT_EQ(ex.wavelengths_nm, base.wavelengths_nm);
        for (size_t i = 0; i < ex.values.size(); ++i) {
            EXPECT_GE(ex.values[i], 0.0);
            EXPECT_LE(ex.values[i] + base.values[i], 1.0 + 1e-12) << ex.wavelengths_nm[i] << " nm";
        }
        // Also after band averaging onto a coarse grid, as the engine checks it.
        Grid g{300, 780, 10};
        auto a = resample(ex, g), b = resample(base, g);
        for (size_t i = 0; i < a.size(); ++i) EXPECT_LE(a[i] + b[i], 1.0 + 1e-12);
        const Spectrum& em = get("fluorescent/" + d + "_em");
        EXPECT_NEAR(maxValue(em), 1.0, 1e-9);
        EXPECT_GT(em.integral(), 0.0);
        // Stokes shift: the emission peaks to the red of the absorption.
        EXPECT_GT(peakWavelength(em), peakWavelength(ex));
    }
}

TEST(Library, BrightenerAbsorbsNearUvAndEmitsBlue) {
    const Spectrum& ex = get("fluorescent/brightener_ex");
    const Spectrum& em = get("fluorescent/brightener_em");
    EXPECT_NEAR(peakWavelength(ex), 350.0, 10.0);
    EXPECT_GE(maxValue(ex), 0.6);
    EXPECT_LE(maxValue(ex), 0.9);
    EXPECT_LT(ex.at(450), 0.01);  // transparent in the visible beyond the violet
    double peak = peakWavelength(em);
    EXPECT_GE(peak, 430.0);
    EXPECT_LE(peak, 450.0);
}

TEST(Library, RhodamineDyesPeakWherePublished) {
    EXPECT_NEAR(peakWavelength(get("fluorescent/orange_dye_ex")), 530.0, 10.0);
    double orangeEm = peakWavelength(get("fluorescent/orange_dye_em"));
    EXPECT_GE(orangeEm, 570.0);
    EXPECT_LE(orangeEm, 610.0);
    EXPECT_NEAR(peakWavelength(get("fluorescent/pink_dye_ex")), 550.0, 10.0);
    EXPECT_NEAR(peakWavelength(get("fluorescent/pink_dye_em")), 578.0, 10.0);
    // Orange paint: little diffuse reflectance in the blue-green, high in the red.
    const Spectrum& base = get("fluorescent/orange_dye_base");
    EXPECT_LT(base.at(500), 0.2);
    EXPECT_GT(base.at(650), 0.8);
}

TEST(Library, BlacklightIsMostlyUvA) {
    const Spectrum& s = get("illuminants/blacklight");
    // The model's peak is 100; the table holds 5 nm band means, the 365 nm band's 75.68.
    EXPECT_NEAR(maxValue(s), 75.678115, 1e-6);
    double uva = s.integrate(315, 400) / s.integral();
    EXPECT_GE(uva, 0.90);
    EXPECT_NEAR(peakWavelength(s), 365.0, 0.6);  // the mercury line on top of the phosphor band
    EXPECT_GT(s.at(404.5), s.at(395));           // 404.7 nm line present
    EXPECT_GT(s.at(436), s.at(425));             // 435.8 nm line present
}

TEST(Library, MetalsMatchKnownReflectances) {
    const Spectrum& au = get("metals/gold");
    EXPECT_NEAR(au.at(450), 0.4, 0.06);
    for (double nm = 650; nm <= 900; nm += 25) EXPECT_GT(au.at(nm), 0.9) << nm;
    const Spectrum& ag = get("metals/silver");
    for (double nm = 450; nm <= 900; nm += 25) EXPECT_GT(ag.at(nm), 0.9) << nm;
    const Spectrum& al = get("metals/aluminium");
    for (double nm = 400; nm <= 700; nm += 25) EXPECT_NEAR(al.at(nm), 0.91, 0.03) << nm;
    EXPECT_LT(al.at(820), al.at(650));  // the interband dip near 800 nm
    EXPECT_LT(al.at(820), al.at(950));
    const Spectrum& cu = get("metals/copper");
    EXPECT_LT(cu.at(450), 0.6);
    EXPECT_GT(cu.at(700), 0.9);
    for (const char* m : {"metals/gold", "metals/silver", "metals/copper", "metals/aluminium"}) {
        EXPECT_LE(get(m).minWavelength(), 300.0) << m;
        EXPECT_GE(get(m).maxWavelength(), 900.0) << m;
        EXPECT_LT(maxValue(get(m)), 1.0) << m;
    }
}

TEST(Library, SuggestsCloseNames) {
    EXPECT_EQ(library().suggest("colorchecker/dark_skn"), "colorchecker/dark_skin");
    EXPECT_EQ(library().suggest("illuminants/D65x"), "illuminants/D65");
    EXPECT_EQ(library().suggest("metals/aluminum"), "metals/aluminium");
    try {
        get("colorchecker/dark_skn");
        FAIL() << "an unknown name was accepted";
    } catch (const Error& e) {
        std::string what = e.what();
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(what.find("did you mean"), std::string::npos) << what;
        EXPECT_NE(what.find("colorchecker/dark_skin"), std::string::npos) << what;
        EXPECT_NE(what.find("library_test"), std::string::npos) << what;  // the Where given
    }
}

// The blacklight is tabulated as the CIE tabulates its lamps: 5 nm band means of the model, so its
// 1.5 nm mercury lines sit in the values of the bands that hold them. Σ v·Δλ then equals the data's
// integral on grids at least as fine as the table (interpolated) and on coarser grids whose centres
// miss the table's wavelengths (band means); a coarser grid on the table's own wavelengths samples
// them (CIE 15's practice for 10 nm work, which E308's weights exist to correct), and band-mean
// resampling conserves the energy there too.
TEST(LibraryResample, BlacklightLinesKeepTheirEnergy) {
    const Spectrum& s = get("illuminants/blacklight");
    ASSERT_EQ(s.wavelengths_nm[1] - s.wavelengths_nm[0], 5.0);
    const double data = s.integral();
    ASSERT_GT(data, 0.0);
    auto energy = [&](Grid g) { return bandSum(resample(s, g), g.step_nm) / data; };
    auto gridFrom = [](double start, double step) {
        return Grid{start, start + step * std::ceil((500.0 - start) / step), step};
    };
    for (double step : {1.0, 5.0})
        for (double start : {300.0, 297.0, 291.5}) EXPECT_NEAR(energy(gridFrom(start, step)), 1.0, 0.01) << step;
    for (double step : {10.0, 20.0, 50.0}) {
        for (double start : {297.0, 291.5}) EXPECT_NEAR(energy(gridFrom(start, step)), 1.0, 0.01) << start << " " << step;
        Grid onTable = gridFrom(300.0, step);
        onTable.resampling = Resampling::BandMean;
        EXPECT_NEAR(energy(onTable), 1.0, 0.01) << step;
    }
    std::printf("  blacklight energy on 300:500:10, sampled at the table's points: %.4f of the data's\n",
                energy(gridFrom(300.0, 10.0)));
    // The 404.66 nm line on the default grid: the 405 nm value is the table's and stands above its
    // neighbours by the line's energy over 5 nm (1.5 % of the phosphor band's, about 20 nm·units).
    Grid g{300, 500, 5};
    auto v = resample(s, g);
    const int band = static_cast<int>(std::lround((405 - 300) / 5));
    EXPECT_EQ(v[size_t(band)], s.values[size_t(band)]);
    const double floor = 0.5 * (v[size_t(band - 1)] + v[size_t(band + 1)]);
    EXPECT_GT((v[size_t(band)] - floor) * 5.0, 5.0);
}

TEST(LibraryResample, ColorCheckerOnItsOwnGridIsUnchanged) {
    const Spectrum& s = get("colorchecker/orange");
    Grid g{400, 700, 5};
    auto v = resample(s, g);
    for (int i = 0; i < g.bands(); ++i) {
        // Linear data averaged over a symmetric band give the centre value only where the data
        // are linear across the band; allow the curvature of the measured curve.
        EXPECT_NEAR(v[i], s.at(g.wavelength(i)), 0.01) << g.wavelength(i);
    }
}
