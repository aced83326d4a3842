// Donaldson matrices: the 2D band-average resampler against known answers (the 1D resampler it
// generalizes, separability of rank-one matrices, conservation of the integral, a delta-like
// matrix that moves energy between two bands), and the CSV reader with its errors.
#include "spectral/bispectral.h"
#include "spectral/csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

Spectrum sampled(std::vector<double> nm, std::vector<double> v, std::string source = "test") {
    Spectrum s;
    s.wavelengths_nm = std::move(nm);
    s.values = std::move(v);
    s.source = std::move(source);
    return s;
}

// peak·exp(−½((λ − c)/σ)²) sampled every `step` nm over [lo, hi].
Spectrum gaussian(double c, double sigma, double lo, double hi, double step, double peak = 1.0) {
    std::vector<double> nm, v;
    for (int i = 0; lo + i * step <= hi + 1e-9; ++i) {
        double l = lo + i * step;
        nm.push_back(l);
        v.push_back(peak * std::exp(-0.5 * (l - c) * (l - c) / (sigma * sigma)));
    }
    return sampled(nm, v, "gaussian");
}

double maxAbs(const std::vector<double>& v) {
    double m = 0;
    for (double x : v) m = std::max(m, std::fabs(x));
    return m;
}

const std::vector<Grid> kGrids = {Grid{300, 740, 5}, Grid{400, 700, 10}, Grid{380, 780, 0.5}, Grid{350, 750, 50},
                                  Grid{455, 655, 2}};

}  // namespace

TEST(Bispectral, BandWeightsReproduceTheOneDimensionalResampler) {
    // Irregular knots, data that end inside the grid (the end rule), a line narrower than a band.
    const std::vector<Spectrum> spectra = {
        gaussian(520, 30, 380, 720, 5),
        sampled({402.3, 410, 431.7, 470, 471, 600.2, 688.8}, {0.3, 0.9, 0.2, 0.7, 0.1, 0.5, 0.8}),
        sampled({549.8, 550, 550.2}, {0, 1, 0}),
        gaussian(450, 80, 200, 2500, 7.3),
    };
    for (const Grid& grid : kGrids)
        for (const Spectrum& s : spectra) {
            SCOPED_TRACE(grid.str() + " " + s.source);
            std::vector<double> expected = resample(s, grid);
            std::vector<double> got = bandWeights(s.wavelengths_nm, grid).apply(s.values);
            ASSERT_EQ(got.size(), expected.size());
            const double scale = std::max(maxAbs(expected), 1e-300);
            for (size_t b = 0; b < got.size(); ++b) EXPECT_NEAR(got[b], expected[b], 1e-13 * scale) << "band " << b;
        }
}

TEST(Bispectral, RankOneMatrixResamplesToTheProductOfItsFactors) {
    // D = u(λin)·w(λout) at the two spectra's knots, bilinear between: the 2D band average must
    // equal resample(u) ⊗ resample(w) whatever the grid, including partial coverage of each axis.
    const Spectrum u = gaussian(360, 25, 300, 480, 3);
    const Spectrum w = sampled({420, 445, 470, 520, 610, 700, 790}, {0, 0.8, 1.0, 0.6, 0.2, 0.05, 0});
    const BispectralMatrix d = BispectralMatrix::outer(u, w);
    for (const Grid& grid : kGrids) {
        SCOPED_TRACE(grid.str());
        const std::vector<double> r = resampleMatrix(d, grid);
        const std::vector<double> ru = resample(u, grid), rw = resample(w, grid);
        const size_t n = ru.size();
        ASSERT_EQ(r.size(), n * n);
        const double scale = maxAbs(ru) * maxAbs(rw);
        double worst = 0;
        for (size_t i = 0; i < n; ++i)
            for (size_t o = 0; o < n; ++o) worst = std::max(worst, std::fabs(r[i * n + o] - ru[i] * rw[o]));
        EXPECT_LE(worst, 1e-13 * scale);
    }
}

TEST(Bispectral, CoarseGridsConserveTheIntegralFineGridsInterpolate) {
    // A rank-two matrix that falls to 0 at its data's ends (3.7 and 4.9 nm apart), inside every
    // grid below. On grids coarser than the data both axes take band means, so Σ R·Δλ² = ∫∫ D
    // (exact for the bilinear function); on finer grids each band pair holds the bilinear
    // interpolant at its centres (spectral/resampling.h, rules 2 and 3). No data point is a band
    // centre (their decimals end in 3 and 7), which would be read as tabulated.
    BispectralMatrix d;
    for (int k = 0; 401.33 + 3.7 * k <= 690; ++k) d.in_nm.push_back(401.33 + 3.7 * k);
    for (int k = 0; 405.17 + 4.9 * k <= 695; ++k) d.out_nm.push_back(405.17 + 4.9 * k);
    for (size_t i = 0; i < d.inCount(); ++i)
        for (size_t o = 0; o < d.outCount(); ++o) {
            const bool edge = i == 0 || o == 0 || i + 1 == d.inCount() || o + 1 == d.outCount();
            const double a = d.in_nm[i], b = d.out_nm[o];
            d.values.push_back(edge ? 0.0
                                    : std::exp(-0.5 * std::pow((a - 450) / 30, 2)) * std::exp(-0.5 * std::pow((b - 520) / 20, 2)) +
                                          0.3 * std::exp(-0.5 * std::pow((a - 560) / 15, 2)) *
                                              std::exp(-0.5 * std::pow((b - 610) / 25, 2)));
        }
    d.validate(Where{"test"});
    const double integral = d.integral();
    ASSERT_GT(integral, 0.0);
    for (const Grid& grid : {Grid{300, 740, 5}, Grid{400, 700, 10}, Grid{350, 750, 50}}) {
        const std::vector<double> r = resampleMatrix(d, grid);
        double sum = 0;
        for (double v : r) sum += v * grid.step_nm * grid.step_nm;
        EXPECT_NEAR(sum, integral, 1e-12 * integral) << grid.str();
    }
    for (const Grid& grid : {Grid{380, 780, 0.5}, Grid{395, 705, 1}}) {
        const std::vector<double> r = resampleMatrix(d, grid);
        const size_t n = size_t(grid.bands());
        for (size_t i = 0; i < n; ++i)
            for (size_t o = 0; o < n; ++o)
                ASSERT_NEAR(r[i * n + o], d.at(grid.wavelength(int(i)), grid.wavelength(int(o))), 1e-12)
                    << grid.str() << " " << i << "," << o;
    }
}

TEST(Bispectral, TabulatedPairsAreCopiedBitForBit) {
    // Band pairs whose centres are both data points hold the tabulated D exactly, on the data's
    // own 5 nm grid and on a 10 nm grid that skips every other point.
    BispectralMatrix d;
    for (double l = 300; l <= 780; l += 5) d.in_nm.push_back(l), d.out_nm.push_back(l);
    for (size_t i = 0; i < d.inCount(); ++i)
        for (size_t o = 0; o < d.outCount(); ++o) d.values.push_back(1e-3 * std::sin(0.1 * double(i)) * std::sin(0.07 * double(o)) + 2e-3);
    d.validate(Where{"test"});
    for (const Grid& grid : {Grid{300, 780, 5}, Grid{400, 700, 10}}) {
        const std::vector<double> r = resampleMatrix(d, grid);
        const size_t n = size_t(grid.bands()), k = size_t(grid.step_nm / 5), skip = size_t((grid.start_nm - 300) / 5);
        for (size_t i = 0; i < n; ++i)
            for (size_t o = 0; o < n; ++o) ASSERT_EQ(r[i * n + o], d.value(skip + i * k, skip + o * k)) << grid.str();
    }
}

TEST(Bispectral, DeltaLikeMatrixMovesEnergyFromOneBandToAnother) {
    // A tent 1 nm wide on each axis at (λin, λout) = (450, 550) nm, peak p: ∫∫ D = p·1 nm·1 nm
    // (each tent's integral is half its base, 2 nm). Under band means, on a 10 nm grid all of it
    // lands in band (450, 550) as p/Δλ² and nothing anywhere else — no diagonal, no leak into
    // neighbours. Under the default rule the band centres (450, 550) are data points, so that band
    // holds the tabulated p, and again nothing leaks.
    const double p = 7.0;
    BispectralMatrix d;
    d.in_nm = {449, 450, 451};
    d.out_nm = {549, 550, 551};
    d.values = {0, 0, 0, 0, p, 0, 0, 0, 0};
    d.validate(Where{"test"});
    EXPECT_DOUBLE_EQ(d.integral(), p);
    EXPECT_DOUBLE_EQ(d.at(450, 550), p);
    EXPECT_DOUBLE_EQ(d.at(450.5, 550), p / 2);
    EXPECT_DOUBLE_EQ(d.at(449.5, 550.5), p / 4);
    EXPECT_EQ(d.at(460, 550), 0.0);
    for (Resampling rule : {Resampling::BandMean, Resampling::Interpolate}) {
        Grid grid{400, 700, 10};
        grid.resampling = rule;
        const size_t n = size_t(grid.bands()), in = 5, out = 15;  // 450 and 550 nm
        const std::vector<double> r = resampleMatrix(d, grid);
        const double expected = rule == Resampling::BandMean ? p / 100.0 : p;
        for (size_t i = 0; i < n; ++i)
            for (size_t o = 0; o < n; ++o) {
                if (i == in && o == out)
                    EXPECT_NEAR(r[i * n + o], expected, 1e-15);
                else
                    EXPECT_EQ(r[i * n + o], 0.0) << i << "," << o;
            }
    }
    // On a grid whose band edge cuts the tent in half (445 | 455 on a 10 nm grid starting at
    // 405; no centre on a data point, the grid coarser than the data), the two bands share it
    // equally under either rule.
    for (Resampling rule : {Resampling::BandMean, Resampling::Interpolate}) {
        Grid shifted{405, 705, 10};
        shifted.resampling = rule;
        const std::vector<double> rs = resampleMatrix(d, shifted);
        const size_t m = size_t(shifted.bands());
        EXPECT_NEAR(rs[4 * m + 14], p / 400.0, 1e-15);  // 445 × 545 nm
        EXPECT_NEAR(rs[5 * m + 15], p / 400.0, 1e-15);  // 455 × 555 nm
        EXPECT_NEAR(rs[4 * m + 15], p / 400.0, 1e-15);
        EXPECT_NEAR(rs[5 * m + 14], p / 400.0, 1e-15);
    }
}

TEST(Bispectral, ValidateRejectsWhatCannotBeAMatrix) {
    auto fails = [](BispectralMatrix d, const std::string& text) {
        try {
            d.validate(Where{"m.csv"});
            ADD_FAILURE() << "accepted; expected '" << text << "'";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadInput);
            EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("m.csv"), std::string::npos) << e.what();
        }
    };
    BispectralMatrix ok;
    ok.in_nm = {400, 410};
    ok.out_nm = {500, 510};
    ok.values = {0, 1, 2, 3};
    EXPECT_NO_THROW(ok.validate(Where{"m.csv"}));
    BispectralMatrix d = ok;
    d.in_nm = {400};
    d.values = {0, 1};
    fails(d, "at least 2 excitation");
    d = ok;
    d.out_nm = {510, 500};
    fails(d, "increase strictly");
    d = ok;
    d.values[2] = NAN;
    fails(d, "D(410 nm, 500 nm) is not a finite number");
    d = ok;
    d.values[1] = -0.5;
    fails(d, "is negative");
    d = ok;
    d.values.pop_back();
    fails(d, "3 values for 2 × 2");
}

// --- The CSV reader -----------------------------------------------------------------------------

namespace {

class BispectralCsv : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = fs::temp_directory_path() / fmt::format("metamer-bispectral-{}-{}", ::getpid(), info->name());
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }

    fs::path write(const std::string& text, const std::string& name = "m.csv") {
        fs::path p = dir / name;
        std::ofstream(p) << text;
        return p;
    }

    // Reading `text` must fail with an input error naming the file, `line` (when > 0) and `what`.
    void expectError(const std::string& text, int line, const std::string& what) {
        fs::path p = write(text);
        try {
            readBispectralCsv(p);
            ADD_FAILURE() << "accepted:\n" << text;
        } catch (const Error& e) {
            std::string msg = e.what();
            EXPECT_EQ(e.code(), ExitCode::BadInput) << msg;
            std::string at = line > 0 ? "m.csv:" + std::to_string(line) + ":" : "m.csv";
            EXPECT_NE(msg.find(at), std::string::npos) << "expected '" << at << "' in: " << msg;
            EXPECT_NE(msg.find(what), std::string::npos) << "expected '" << what << "' in: " << msg;
        }
    }

    fs::path dir;
};

}  // namespace

TEST_F(BispectralCsv, ReadsTheDocumentedLayout) {
    fs::path p = write(
        "# a Donaldson matrix, nm^-1\n"
        "in\\out nm, 500, 520.5, 540\n"
        "\n"
        "350, 0, 0.001, 2e-3\n"
        "# comment between rows\n"
        "400 ,0.5,0.25 , 0\n"
        "450,0,0,0\n");
    BispectralMatrix d = readBispectralCsv(p);
    EXPECT_EQ(d.in_nm, (std::vector<double>{350, 400, 450}));
    EXPECT_EQ(d.out_nm, (std::vector<double>{500, 520.5, 540}));
    EXPECT_EQ(d.values, (std::vector<double>{0, 0.001, 0.002, 0.5, 0.25, 0, 0, 0, 0}));
    EXPECT_DOUBLE_EQ(d.value(1, 1), 0.25);
    EXPECT_NO_THROW(d.validate(Where{p.string()}));
    // An empty label is a label.
    EXPECT_NO_THROW(readBispectralCsv(write(",500,510\n400,1,2\n410,3,4\n")));
}

TEST_F(BispectralCsv, EveryErrorNamesTheFileLineAndColumn) {
    expectError("", 0, "empty: expected a header row");
    expectError("# only a comment\n\n", 0, "empty");
    expectError("nm,500,510\n", 0, "at least 2 excitation rows");
    expectError("nm,500,510\n400,1,2\n", 0, "found 1");
    expectError("400,500,510\n400,1,2\n410,3,4\n", 1, "the first field '400' is a number");
    expectError("nm,500\n400,1\n410,2\n", 1, "lists 1 emission wavelength(s)");
    expectError("nm,500,abc\n400,1,2\n410,3,4\n", 1, "column 3: 'abc' is not an emission wavelength");
    expectError("nm,510,500\n400,1,2\n410,3,4\n", 1, "column 3: emission wavelengths must increase strictly: 500 nm follows 510 nm");
    expectError("nm,500,500\n400,1,2\n410,3,4\n", 1, "must increase strictly");
    expectError("nm,-500,510\n400,1,2\n410,3,4\n", 1, "column 2: emission wavelength '-500' must be a positive finite number");
    expectError("nm,500,510\n400,1,2\nx,3,4\n", 3, "column 1: 'x' is not an excitation wavelength");
    expectError("nm,500,510\n410,1,2\n400,3,4\n", 3, "excitation wavelengths must increase strictly: 400 nm follows 410 nm");
    expectError("nm,500,510\n400,1,2\n400,3,4\n", 3, "400 nm follows 400 nm");
    expectError("nm,500,510\n400,1,2\n410,3\n", 3, "expected 2 values (one per emission wavelength in the header), got 1");
    expectError("nm,500,510\n400,1,2\n410,3,4,5\n", 3, "got 3");
    expectError("nm,500,510\n400,1,nan\n410,3,4\n", 2, "column 3: 'nan' is not a finite number");
    expectError("nm,500,510\n400,1,2\n410,1e999,4\n", 3, "column 2: '1e999' is not a finite number");
    expectError("nm,500,510\n400,1,\n410,3,4\n", 2, "column 3: '' is not a finite number");
    expectError("nm,500,510\n400,1,-0.25\n410,3,4\n", 2, "column 3: -0.25 is negative");
    expectError("nm;500;510\n400;1;2\n", 1, "lists 0 emission wavelength(s)");
}

TEST_F(BispectralCsv, MissingFileIsAnInputError) {
    try {
        readBispectralCsv(dir / "absent.csv");
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(std::string(e.what()).find("absent.csv"), std::string::npos);
    }
}
