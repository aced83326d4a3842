// metamer bench: the Pareto front on hand-made rows, a tiny sweep on the GPU (scenes/metamers.json
// under illuminant A, where the RGB mode is known to be wrong), the files it writes, and the plot.
#include "bench/bench.h"
#include "bench/plot.h"
#include "support/gpu.h"
#include "support/png_chunks.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <limits>
#include <unistd.h>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

BenchRow row(const char* mode, double step, double ms, double p95) {
    BenchRow r;
    r.mode = parseMode(mode, Where{});
    r.stepNm = step;
    r.renderMsMedian = ms;
    r.de2000P95 = p95;
    return r;
}

fs::path scratch(const std::string& name) {
    fs::path d = fs::temp_directory_path() / fmt::format("metamer-bench-{}-{}", name, getpid());
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::string firstDataLine(const fs::path& csv, int* rows) {
    std::ifstream in(csv);
    std::string header, line;
    *rows = 0;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        if (header.empty()) header = line;
        else ++*rows;
    }
    return header;
}

const BenchRow& find(const BenchResult& r, const std::string& mode, double step) {
    for (const auto& row : r.rows)
        if (row.mode.name() == mode && row.stepNm == step) return row;
    throw std::runtime_error("no row " + mode);
}

}  // namespace

TEST(BenchPareto, DominatedRowsAreLeftOutAndTheFrontIsInTimeOrder) {
    std::vector<BenchRow> rows = {row("full", 5, 30, 0.01), row("rgb", 5, 10, 3.0), row("ac1c2:4", 5, 12, 4.0),
                                  row("ac1c2:8", 5, 14, 0.5), row("full", 20, 16, 0.6), row("full", 1, 90, 0)};
    // ac1c2:4 is slower and worse than rgb; full 20 nm slower and worse than ac1c2:8.
    EXPECT_EQ(paretoFront(rows), (std::vector<size_t>{1, 3, 0, 5}));
}

TEST(BenchPareto, TiesInOneCoordinateAreBrokenByTheOtherAndEqualRowsAreBothKept) {
    // Same time: the lower error wins. Same error: the faster wins.
    EXPECT_EQ(paretoFront({row("full", 5, 10, 1.0), row("full", 10, 10, 0.5)}), (std::vector<size_t>{1}));
    EXPECT_EQ(paretoFront({row("full", 5, 10, 1.0), row("full", 10, 8, 1.0)}), (std::vector<size_t>{1}));
    // Identical numbers: neither beats the other.
    EXPECT_EQ(paretoFront({row("rgb", 5, 10, 1.0), row("rgb", 10, 10, 1.0)}), (std::vector<size_t>{0, 1}));
}

TEST(BenchPareto, SkippedRowsAndMissingNumbersAreNeverOnTheFront) {
    BenchRow skipped = row("ac1c2:8", 20, 1, 0);
    skipped.skippedReason = "sample outside the grid";
    std::vector<BenchRow> rows = {skipped, row("full", 5, kNaN, 0.1), row("full", 10, 5, kNaN), row("rgb", 5, 20, 2)};
    EXPECT_EQ(paretoFront(rows), (std::vector<size_t>{3}));
    EXPECT_TRUE(paretoFront({}).empty());
}

// The sweep the brief asks for, tiny: full and rgb at 5 and 10 nm under A on 16×16 pixels.
TEST(BenchSweep, FullBeatsRgbUnderIlluminantAAndTheFilesAreWritten) {
    uint32_t before = test::gpu().validationErrors();
    BenchConfig c;
    c.modes = {parseMode("full", Where{}), parseMode("rgb", Where{})};
    c.steps = {5, 10};
    c.frames = 2;
    c.size = std::pair{16, 16};
    c.overrides = {"lights.0.spectrum=illuminants/A"};
    std::vector<std::string> lines;
    BenchResult r = runBench(fs::path(METAMER_SOURCE_DIR) / "scenes" / "metamers.json", c, test::gpu(),
                             [&](const std::string& l) { lines.push_back(l); });
    EXPECT_NO_VALIDATION_ERRORS(before);

    ASSERT_EQ(r.rows.size(), 4u);
    EXPECT_EQ(r.width, 16);
    EXPECT_EQ(r.height, 16);
    EXPECT_EQ(r.referenceGrid.str(), "380:780:1");
    EXPECT_GT(r.comparedPixels, 100u);
    EXPECT_FALSE(r.device.empty());
    for (const auto& row : r.rows) {
        SCOPED_TRACE(row.label());
        EXPECT_FALSE(row.skipped()) << row.skippedReason;
        EXPECT_TRUE(std::isfinite(row.renderMsMedian) && row.renderMsMedian > 0);
        EXPECT_TRUE(std::isfinite(row.renderMsFirst) && row.renderMsFirst > 0);
        EXPECT_GE(row.runMs, row.renderMsFirst);
        EXPECT_TRUE(std::isfinite(row.cubeMsMedian) && row.cubeMsMedian > 0);
        EXPECT_TRUE(std::isfinite(row.de2000P95));
        EXPECT_LE(row.de2000Mean, row.de2000Max);
        EXPECT_LE(row.de2000P95, row.de2000Max);
    }
    const BenchRow& full5 = find(r, "full", 5);
    const BenchRow& rgb5 = find(r, "rgb", 5);
    EXPECT_EQ(full5.grid, "380:780:5");
    EXPECT_EQ(full5.channels, 81);
    EXPECT_EQ(rgb5.channels, 3);
    // Full spectral at 5 nm is within a small fraction of a JND of 1 nm; RGB misses the pair under A.
    EXPECT_LT(full5.de2000P95, 0.2);
    EXPECT_GT(rgb5.de2000P95, 1.0);
    EXPECT_LT(full5.de2000P95 * 10, rgb5.de2000P95);
    EXPECT_TRUE(std::isfinite(full5.spectralRmseRelative));
    EXPECT_LT(full5.spectralRmseRelative, 0.05);
    EXPECT_TRUE(std::isnan(rgb5.spectralRmseRelative));
    EXPECT_TRUE(std::isnan(find(r, "rgb", 10).spectralRmseRelative));

    // Progress: the reference, then one line per configuration.
    ASSERT_EQ(lines.size(), 5u);
    EXPECT_EQ(lines[0].rfind("[ref] full at 1 nm", 0), 0u) << lines[0];
    EXPECT_EQ(lines[2].rfind("[2/4] full at 10 nm: ", 0), 0u) << lines[2];
    EXPECT_NE(lines[2].find("ΔE00 p95"), std::string::npos) << lines[2];

    fs::path dir = scratch("sweep");
    writeBenchCsv(dir / "metamers.bench.csv", r);
    writeBenchJson(dir / "metamers.bench.json", r);
    writeBenchPlot(dir / "metamers.bench.png", r);
    int rows = 0;
    EXPECT_EQ(firstDataLine(dir / "metamers.bench.csv", &rows),
              "mode,step_nm,grid,channels,render_ms_median,render_ms_first,cube_ms_median,run_ms,de2000_mean,"
              "de2000_p95,de2000_max,spectral_rmse_relative,skipped_reason");
    EXPECT_EQ(rows, 4);
    nlohmann::json j = nlohmann::json::parse(std::ifstream(dir / "metamers.bench.json"));
    EXPECT_EQ(j["rows"].size(), 4u);
    EXPECT_EQ(j["frames"], 2);
    EXPECT_EQ(j["width"], 16);
    EXPECT_FALSE(j["device"].get<std::string>().empty());
    EXPECT_TRUE(j["rows"][2]["spectral_rmse_relative"].is_null());  // rgb 5 nm
    EXPECT_TRUE(j["rows"][0]["spectral_rmse_relative"].is_number());
    auto in = OIIO::ImageInput::open((dir / "metamers.bench.png").string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().width, 960);
    EXPECT_EQ(in->spec().nchannels, 3);
    in->close();
    EXPECT_TRUE(test::hasPngChunk(dir / "metamers.bench.png", "sRGB")) << "its colours are sRGB counts, tagged so";
    fs::remove_all(dir);
}

// An AC1C2 sample outside one configuration's grid is that configuration's problem, not the sweep's.
TEST(BenchSweep, AConfigurationWithAnInputErrorIsSkippedWithItsReason) {
    uint32_t before = test::gpu().validationErrors();
    BenchConfig c;
    c.modes = {parseMode("ac1c2:8", Where{}), parseMode("ac1c2:4", Where{})};
    c.steps = {20};
    c.frames = 1;
    c.size = std::pair{8, 8};
    // 410..780 nm: ac1c2:8's first sample, 400.25 nm, falls outside; ac1c2:4 starts at 436 nm.
    c.overrides = {"grid.start_nm=410"};
    BenchResult r = runBench(fs::path(METAMER_SOURCE_DIR) / "scenes" / "metamers.json", c, test::gpu());
    EXPECT_NO_VALIDATION_ERRORS(before);
    ASSERT_EQ(r.rows.size(), 2u);
    EXPECT_TRUE(r.rows[0].skipped());
    EXPECT_NE(r.rows[0].skippedReason.find("400.25"), std::string::npos) << r.rows[0].skippedReason;
    EXPECT_TRUE(std::isnan(r.rows[0].renderMsMedian));
    EXPECT_FALSE(r.rows[1].skipped()) << r.rows[1].skippedReason;
    // 410 + 18 × 20 = 770: the step does not divide 410..780, and the grid says so.
    EXPECT_EQ(r.rows[1].grid, "410:770:20");
    ASSERT_FALSE(r.notes.empty());
    EXPECT_NE(r.notes[0].find("410:770:20"), std::string::npos) << r.notes[0];
    // One frame: the median is that frame.
    EXPECT_EQ(r.rows[1].renderMsMedian, r.rows[1].renderMsFirst);

    fs::path dir = scratch("skip");
    writeBenchCsv(dir / "s.csv", r);
    std::ifstream in(dir / "s.csv");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("ac1c2:8,20,410:770:20,,,,,,,,,"), std::string::npos) << text;
    fs::remove_all(dir);
}

TEST(BenchPlot, WithoutTheFontThePlotIsDrawnWithoutText) {
    BenchResult r;
    r.scene = r.sceneName = "hand";
    r.device = "none";
    r.frames = 3;
    r.rows = {row("full", 5, 30, 0.01), row("rgb", 5, 10, 3.0), row("full", 1, 90, 0)};
    fs::path dir = scratch("plot");
    BenchPlotOptions o;
    o.font = dir / "no-such-font.ttf";
    WarningSink old = setWarningSink([](const std::string&) {});
    EXPECT_FALSE(writeBenchPlot(dir / "plain.png", r, o));
    setWarningSink(old);
    EXPECT_TRUE(fs::exists(dir / "plain.png"));
    if (fs::exists(benchPlotFont())) EXPECT_TRUE(writeBenchPlot(dir / "text.png", r));
    fs::remove_all(dir);
}
