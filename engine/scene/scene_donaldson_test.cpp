// Scenes with Donaldson-matrix fluorescence: the "matrix" form of a material's fluorescence (CSV,
// bispectral EXR or a library name), its scale, the coverage policy on both axes, the photon
// balance warning, and every loading error naming the scene file and the key (and the matrix
// file's line where one is at fault).
#include "scene/scene_json.h"
#include "scene/scene_on_grid.h"
#include "support/capture_warnings.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cmath>
#include <fstream>

using namespace metamer;
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

using test::CaptureWarnings;

// A folder holding the scene, its matrix files and a small spectra library of its own.
class SceneDonaldson : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        root = fs::temp_directory_path() / fmt::format("metamer-donaldson-{}-{}", ::getpid(), info->name());
        fs::remove_all(root);
        fs::create_directories(root / "scene");
        fs::create_directories(root / "lib" / "illuminants");
        fs::create_directories(root / "lib" / "fluorescent");
        write(root / "lib" / "illuminants" / "E.csv", "wavelength_nm,value\n200,100\n2500,100\n");
        // λin 300–500 nm, λout 400–700 nm: the grid 400:500:10 is covered on both axes.
        write(root / "scene" / "m.csv", matrixCsv({300, 400, 450, 500}, {400, 500, 600, 700}, 0.01));
        write(root / "lib" / "fluorescent" / "libm.csv", matrixCsv({300, 500}, {400, 700}, 0.02));
        lib = std::make_unique<SpectrumLibrary>(root / "lib");
    }
    void TearDown() override { fs::remove_all(root); }

    static void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

    // A matrix with every value `v`, except 0 where λout ≤ λin.
    static std::string matrixCsv(const std::vector<double>& in, const std::vector<double>& out, double v) {
        std::string s = "nm";
        for (double o : out) s += fmt::format(",{:g}", o);
        s += "\n";
        for (double i : in) {
            s += fmt::format("{:g}", i);
            for (double o : out) s += fmt::format(",{:g}", o > i ? v : 0.0);
            s += "\n";
        }
        return s;
    }

    Json scene(const Json& fluorescence) const {
        Json doc = Json::parse(R"({
          "grid": {"start_nm": 400, "end_nm": 500, "step_nm": 10},
          "camera": {"position": [0, 0, 3], "target": [0, 0, 0], "width": 8, "height": 8},
          "lights": [{"type": "directional", "direction": [0, 0, -1], "spectrum": "illuminants/E", "scale": 0.01}],
          "materials": {"m": {"diffuse": 0.1}},
          "objects": [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [1, 1], "material": "m"}]
        })");
        doc["materials"]["m"]["fluorescence"] = fluorescence;
        return doc;
    }

    Scene load(const Json& doc) const {
        return loadSceneFromString(doc.dump(2), root / "scene" / "s.json", *lib);
    }

    // Loading (and resampling, when `onGrid`) must fail with an input error that contains `what`.
    std::string expectError(const Json& doc, const std::string& what, bool onGrid = false,
                            CoveragePolicy policy = CoveragePolicy::ZeroWithWarning) const {
        CaptureWarnings quiet;
        try {
            Scene s = load(doc);
            if (onGrid) resampleScene(s, s.grid, policy);
            ADD_FAILURE() << "accepted; expected '" << what << "'";
        } catch (const Error& e) {
            std::string msg = e.what();
            EXPECT_EQ(e.code(), ExitCode::BadInput) << msg;
            EXPECT_NE(msg.find("s.json"), std::string::npos) << "does not name the scene: " << msg;
            EXPECT_NE(msg.find(what), std::string::npos) << "expected '" << what << "' in: " << msg;
            return msg;
        }
        return "";
    }

    fs::path root;
    std::unique_ptr<SpectrumLibrary> lib;
};

}  // namespace

TEST_F(SceneDonaldson, CsvMatrixLoadsAndGoesOnTheGridWithItsScale) {
    Scene s = load(scene({{"matrix", "m.csv"}, {"scale", 2.5}}));
    ASSERT_TRUE(s.materials[0].fluorescence);
    ASSERT_TRUE(s.materials[0].fluorescence->matrix);
    const SceneMatrix& m = *s.materials[0].fluorescence->matrix;
    EXPECT_EQ(m.scale, 2.5);
    EXPECT_EQ(m.matrix.source, "m.csv");
    EXPECT_EQ(m.where.key, "materials.m.fluorescence.matrix");
    EXPECT_EQ(m.matrix.in_nm, (std::vector<double>{300, 400, 450, 500}));
    EXPECT_TRUE(s.hasFluorescence());
    SceneOnGrid g = resampleScene(s, s.grid, CoveragePolicy::Error);
    const MaterialOnGrid& mg = g.materials[0];
    EXPECT_TRUE(mg.fluorescent);
    EXPECT_TRUE(mg.isMatrix());
    EXPECT_TRUE(mg.excitation.empty());
    const std::vector<double> expected = resampleMatrix(m.matrix, s.grid);
    ASSERT_EQ(mg.donaldson.size(), expected.size());
    for (size_t k = 0; k < expected.size(); ++k) EXPECT_DOUBLE_EQ(mg.donaldson[k], 2.5 * expected[k]);
    // By hand: between the rows λin = 400 and 450 nm both read D = 0.01·(λout − 400)/100 for
    // λout in 400–500 nm, so band (440, 480) is 2.5 × 0.01 × 0.8. λout = 400 nm is a data point,
    // so band (440, 400) reads the tabulated D(·, 400) = 0. Under band means it holds that line's
    // mean over [400, 405] (0.01 × 2.5/100) on half the band and D(λ, 400) = 0 on the half below
    // the data (the end rule).
    const size_t n = size_t(s.grid.bands());
    EXPECT_NEAR(mg.donaldson[4 * n + 8], 0.02, 1e-15);
    EXPECT_EQ(mg.donaldson[4 * n + 0], 0.0);
    Grid bandMean = s.grid;
    bandMean.resampling = Resampling::BandMean;
    const SceneOnGrid gm = resampleScene(s, bandMean, CoveragePolicy::Error);
    EXPECT_NEAR(gm.materials[0].donaldson[4 * n + 8], 0.02, 1e-15);
    EXPECT_NEAR(gm.materials[0].donaldson[4 * n + 0], 2.5 * 0.01 * 2.5 / 100 / 2, 1e-17);
}

TEST_F(SceneDonaldson, LibraryNamesAndBispectralExr) {
    Scene s = load(scene({{"matrix", "fluorescent/libm"}}));
    EXPECT_EQ(s.materials[0].fluorescence->matrix->matrix.value(0, 1), 0.02);
    EXPECT_EQ(s.materials[0].fluorescence->matrix->matrix.source, "fluorescent/libm");
    // An EXR beside the scene, with a reflective channel that is left out with a warning.
    {
        OIIO::ImageSpec spec(1, 1, 5, OIIO::TypeDesc::FLOAT);
        spec.channelnames = {"T.300nm.400nm", "T.300nm.700nm", "T.500nm.400nm", "T.500nm.700nm", "T.450nm"};
        std::vector<float> px = {0.5f, 0.25f, 0.0f, 0.125f, 0.8f};
        auto out = OIIO::ImageOutput::create((root / "scene" / "m.exr").string());
        ASSERT_TRUE(out->open((root / "scene" / "m.exr").string(), spec));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
        out->close();
    }
    CaptureWarnings warnings;
    Scene e = load(scene({{"matrix", "m.exr"}}));
    const BispectralMatrix& d = e.materials[0].fluorescence->matrix->matrix;
    EXPECT_EQ(d.values, (std::vector<double>{0.5, 0.25, 0.0, 0.125}));
    ASSERT_EQ(warnings.lines().size(), 1u);
    EXPECT_NE(warnings.lines()[0].find("materials.m.fluorescence.matrix"), std::string::npos) << warnings.lines()[0];
    EXPECT_NE(warnings.lines()[0].find("1 reflective T.<λ>nm channel(s) ignored"), std::string::npos)
        << warnings.lines()[0];
    // A library EXR is found when there is no CSV of that name.
    fs::copy_file(root / "scene" / "m.exr", root / "lib" / "fluorescent" / "exr_only.exr");
    Scene le = load(scene({{"matrix", "fluorescent/exr_only"}}));
    EXPECT_EQ(le.materials[0].fluorescence->matrix->matrix.values, d.values);
}

TEST_F(SceneDonaldson, FormAndKeyErrorsNameTheKey) {
    expectError(scene({{"matrix", "m.csv"}, {"excitation", 0.5}}),
                "materials.m.fluorescence.excitation: not allowed with 'matrix'");
    expectError(scene({{"matrix", "m.csv"}, {"quantum_yield", 0.5}}),
                "materials.m.fluorescence.quantum_yield: not allowed with 'matrix'");
    expectError(scene({{"excitation", 0.5}, {"emission", "illuminants/E"}, {"quantum_yield", 1}, {"scale", 2}}),
                "materials.m.fluorescence.scale: 'scale' goes with 'matrix'");
    expectError(scene({{"matrix", "m.csv"}, {"gain", 2}}),
                "materials.m.fluorescence.gain: unknown key for a Donaldson-matrix fluorescence");
    expectError(scene({{"matrix", 3}}), "materials.m.fluorescence.matrix: expected a Donaldson matrix");
    expectError(scene({{"matrix", ""}}), "materials.m.fluorescence.matrix: expected a Donaldson matrix file name");
    expectError(scene({{"matrix", "m.csv"}, {"scale", -1}}), "materials.m.fluorescence.scale: must be ≥ 0");
    expectError(scene({{"matrix", "absent.csv"}}), "materials.m.fluorescence.matrix: Donaldson matrix file");
    expectError(scene({{"matrix", "absent.exr"}}), "not found");
    expectError(scene({{"matrix", "fluorescent/none"}}),
                "materials.m.fluorescence.matrix: no Donaldson matrix 'fluorescent/none' in the spectra library");
    write(root / "outside.csv", matrixCsv({300, 500}, {400, 700}, 0.01));
    expectError(scene({{"matrix", "../outside.csv"}}), "is outside the folders a scene may read");
    expectError(scene({{"matrix", "../outside"}}), "is outside the folders a scene may read");  // a library name
    expectError(scene({{"matrix", "../../nowhere"}}), "no Donaldson matrix '../../nowhere'");
}

TEST_F(SceneDonaldson, MatrixFileErrorsNameTheKeyFileLineAndColumn) {
    write(root / "scene" / "nan.csv", "nm,400,500\n300,0,0.1\n400,nan,0.2\n");
    expectError(scene({{"matrix", "nan.csv"}}),
                "materials.m.fluorescence.matrix: " + (root / "scene" / "nan.csv").string() +
                    ":3: column 2: 'nan' is not a finite number");
    // A spectrum file is not a matrix: its header names no wavelengths.
    write(root / "scene" / "spectrum.csv", "wavelength_nm,value\n400,1\n500,2\n");
    expectError(scene({{"matrix", "spectrum.csv"}}), "spectrum.csv:1: column 2: 'value' is not an emission wavelength");
    write(root / "scene" / "bad.exr", "not an image");
    expectError(scene({{"matrix", "bad.exr"}}), "bad.exr");
}

TEST_F(SceneDonaldson, CoveragePolicyAppliesToBothAxes) {
    // λin 600–700 nm lies entirely above the grid 400–500 nm.
    write(root / "scene" / "red.csv", matrixCsv({600, 700}, {400, 700}, 0.01));
    expectError(scene({{"matrix", "red.csv"}}),
                "Donaldson matrix 'red.csv': its excitation (λin) wavelengths cover 600–700 nm, entirely outside the "
                "grid 400–500 nm",
                true);
    write(root / "scene" / "blue.csv", matrixCsv({300, 500}, {200, 300}, 0.01));
    expectError(scene({{"matrix", "blue.csv"}}), "its emission (λout) wavelengths cover 200–300 nm", true);
    // Partly outside: a warning naming the key and both ranges, or an error when strict.
    write(root / "scene" / "part.csv", matrixCsv({300, 450}, {420, 700}, 0.01));
    {
        CaptureWarnings warnings;
        Scene s = load(scene({{"matrix", "part.csv"}}));
        SceneOnGrid g = resampleScene(s, s.grid);
        ASSERT_EQ(warnings.lines().size(), 1u);
        EXPECT_NE(warnings.lines()[0].find("materials.m.fluorescence.matrix: Donaldson matrix 'part.csv' covers λin "
                                           "300–450 nm and λout 420–700 nm but the grid is 400–500 nm; bands outside "
                                           "the data are 0"),
                  std::string::npos)
            << warnings.lines()[0];
        const size_t n = size_t(s.grid.bands());
        EXPECT_EQ(g.materials[0].donaldson[9 * n + 10], 0.0);  // λin 490 nm: no data
        EXPECT_EQ(g.materials[0].donaldson[0 * n + 1], 0.0);    // λout 410 nm: no data
        EXPECT_GT(g.materials[0].donaldson[0 * n + 5], 0.0);
    }
    expectError(scene({{"matrix", "part.csv"}}), "(--strict-coverage)", true, CoveragePolicy::Error);
}

TEST_F(SceneDonaldson, PhotonBalanceAndOverflow) {
    // 0.05 nm⁻¹ over 200 nm of emission re-emits ~10 photons per photon: a warning, at load.
    write(root / "scene" / "bright.csv", matrixCsv({300, 500}, {400, 700}, 0.05));
    {
        CaptureWarnings warnings;
        Scene s = load(scene({{"matrix", "bright.csv"}}));
        resampleScene(s, s.grid);
        ASSERT_EQ(warnings.lines().size(), 1u);
        EXPECT_NE(warnings.lines()[0].find("photons re-emitted per photon received"), std::string::npos)
            << warnings.lines()[0];
    }
    {
        CaptureWarnings warnings;
        Scene s = load(scene({{"matrix", "m.csv"}}));  // at most ≈ 0.6 photons + the diffuse 0.1
        resampleScene(s, s.grid);
        EXPECT_TRUE(warnings.lines().empty()) << warnings.lines().front();
    }
    write(root / "scene" / "big.csv", matrixCsv({300, 500}, {400, 700}, 100));
    expectError(scene({{"matrix", "big.csv"}, {"scale", 1e308}}), "× scale 1e+308 overflows a double", true);
}

TEST(BundledDonaldson, TheTwoFluorophorePaintChangesColourWithTheExcitation) {
    // scenes/fluorescent-matrix.json's paint (spectra/README.md, "Donaldson matrices"): excited in
    // the UV it emits mostly the brightener's violet-blue, in the green only the dye's pink. In a
    // rank-one matrix every row would have the same shape.
    const fs::path root = METAMER_SOURCE_DIR;
    SpectrumLibrary lib(root / "spectra");
    ASSERT_TRUE(lib.contains("fluorescent/brightened_pink_donaldson")) << "spectra/ lost its Donaldson matrix";
    CaptureWarnings quiet;
    const Scene s = loadScene(root / "scenes" / "fluorescent-matrix.json", lib);
    const SceneOnGrid g = resampleScene(s, s.grid, CoveragePolicy::Error);
    EXPECT_TRUE(quiet.lines().empty()) << quiet.lines().front();
    size_t m = 0;
    while (m < s.materials.size() && s.materials[m].name != "brightened_pink") ++m;
    ASSERT_LT(m, s.materials.size());
    ASSERT_TRUE(g.materials[m].isMatrix());
    const std::vector<double>& nm = g.wavelengths_nm;
    const size_t n = nm.size();
    auto row = [&](double in) {
        const size_t i = size_t(std::lround((in - nm[0]) / s.grid.step_nm));
        return std::vector<double>(g.materials[m].donaldson.begin() + i * n, g.materials[m].donaldson.begin() + (i + 1) * n);
    };
    auto peak = [&](const std::vector<double>& r) { return nm[size_t(std::max_element(r.begin(), r.end()) - r.begin())]; };
    auto redShare = [&](const std::vector<double>& r) {
        double red = 0, all = 0;
        for (size_t o = 0; o < n; ++o) {
            all += r[o];
            if (nm[o] > 520) red += r[o];
        }
        return red / all;
    };
    const std::vector<double> uv = row(360), green = row(540);
    EXPECT_NEAR(peak(uv), 440, 10);
    EXPECT_NEAR(peak(green), 580, 10);
    EXPECT_LT(redShare(uv), 0.3);
    EXPECT_GT(redShare(green), 0.99);
    // Photons: with the diffuse, at most what the material receives at every λin.
    for (size_t i = 0; i < n; ++i) {
        double yield = 0;
        for (size_t o = 0; o < n; ++o) yield += g.materials[m].donaldson[i * n + o] * nm[o] / nm[i] * s.grid.step_nm;
        EXPECT_LE(g.materials[m].diffuse[i] + yield, 0.91) << nm[i] << " nm";
    }
}
