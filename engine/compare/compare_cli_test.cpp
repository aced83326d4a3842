// `metamer compare` as a user runs it: the summary, the files it writes, exit codes 0/1/2.
#include "compare/compare_test_util.h"
#include "io/image_file.h"
#include "io/spectral_exr.h"
#include "support/cli.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>

using namespace metamer;
using metamer::test::smoothCube;
namespace fs = std::filesystem;

namespace {

using CliResult = metamer::test::CliRun;

CliResult runCompareCli(const std::string& args) { return metamer::test::runMetamer("compare " + args); }

bool has(const CliResult& r, const std::string& text) { return r.output.find(text) != std::string::npos; }

class CompareCli : public metamer::test::ScratchDir {
protected:
    void SetUp() override {
        ScratchDir::SetUp();
        SpectralCube ref = smoothCube(8, 6, Grid{400, 700, 10});
        writeSpectralExr(dir / "ref.exr", ref);
        writeSpectralExr(dir / "same.exr", ref);
        SpectralCube off = ref;
        for (int y = 0; y < 6; ++y)
            for (int x = 0; x < 8; ++x) off.at(x, y, 12) *= 1.005f;  // +0.5% at 520 nm
        writeSpectralExr(dir / "off.exr", off);
        writeSpectralExr(dir / "small.exr", smoothCube(4, 6, Grid{400, 700, 10}));
        writeSpectralExr(dir / "fine.exr", smoothCube(8, 6, Grid{400, 700, 5}));
        strict = write("strict.json", R"({"description": "test", "max_rel": 1e-3})").string();
        loose = write("loose.json", R"({"max_rel": 1e-2, "rmse_relative": 1e-2})").string();
    }
    std::string f(const char* name) const { return (dir / name).string(); }
    std::string strict, loose;
};

}  // namespace

TEST_F(CompareCli, IdenticalCubesExit0) {
    CliResult r = runCompareCli(f("same.exr") + " " + f("ref.exr") + " --tolerance " + strict);
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(has(r, "identical")) << r.output;
    EXPECT_TRUE(has(r, "ΔE2000")) << r.output;
    EXPECT_TRUE(has(r, "PASS")) << r.output;
}

TEST_F(CompareCli, WithinTheToleranceExits0OutsideExits1WithEachFailure) {
    CliResult within = runCompareCli(f("off.exr") + " " + f("ref.exr") + " --tolerance " + loose);
    EXPECT_EQ(within.code, 0) << within.output;
    EXPECT_TRUE(has(within, "PASS")) << within.output;
    EXPECT_TRUE(has(within, "520 nm")) << within.output;  // the worst band

    CliResult outside = runCompareCli(f("off.exr") + " " + f("ref.exr") + " --tolerance " + strict);
    EXPECT_EQ(outside.code, 1) << outside.output;
    EXPECT_TRUE(has(outside, "FAIL")) << outside.output;
    EXPECT_TRUE(has(outside, "max_rel 5e-03 > 1e-03")) << outside.output;

    CliResult none = runCompareCli(f("off.exr") + " " + f("ref.exr"));  // no tolerance: a report, exit 0
    EXPECT_EQ(none.code, 0) << none.output;
    EXPECT_TRUE(has(none, "max rel error     5e-03")) << none.output;
}

TEST_F(CompareCli, VerbosePrintsEveryBand) {
    CliResult r = runCompareCli(f("off.exr") + " " + f("ref.exr") + " --verbose --no-delta-e");
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(has(r, "400 nm")) << r.output;
    EXPECT_TRUE(has(r, "700 nm")) << r.output;
    EXPECT_FALSE(has(r, "ΔE2000")) << r.output;
}

TEST_F(CompareCli, UnusableInputExits2NamingTheFiles) {
    CliResult size = runCompareCli(f("small.exr") + " " + f("ref.exr"));
    EXPECT_EQ(size.code, 2) << size.output;
    EXPECT_TRUE(has(size, "small.exr")) << size.output;
    EXPECT_TRUE(has(size, "ref.exr")) << size.output;

    CliResult grid = runCompareCli(f("fine.exr") + " " + f("ref.exr"));
    EXPECT_EQ(grid.code, 2) << grid.output;
    EXPECT_TRUE(has(grid, "--resample")) << grid.output;

    CliResult missing = runCompareCli(f("nothing.exr") + " " + f("ref.exr"));
    EXPECT_EQ(missing.code, 2) << missing.output;
    EXPECT_TRUE(has(missing, "nothing.exr: image not found")) << missing.output;

    std::string bad = write("bad.json", R"({"max_rell": 1e-3})").string();
    CliResult tolerance = runCompareCli(f("same.exr") + " " + f("ref.exr") + " --tolerance " + bad);
    EXPECT_EQ(tolerance.code, 2) << tolerance.output;
    EXPECT_TRUE(has(tolerance, "bad.json:1: max_rell")) << tolerance.output;
    EXPECT_TRUE(has(tolerance, "did you mean 'max_rel'?")) << tolerance.output;

    CliResult detector = runCompareCli(f("same.exr") + " " + f("ref.exr") + " --detector cie1391");
    EXPECT_EQ(detector.code, 2) << detector.output;
    EXPECT_TRUE(has(detector, "--detector")) << detector.output;

    CliResult flags = runCompareCli(f("same.exr"));
    EXPECT_EQ(flags.code, 2) << flags.output;
}

TEST_F(CompareCli, ResampleMakesA5nmCubeComparableTo10nm) {
    CliResult r = runCompareCli(f("fine.exr") + " " + f("ref.exr") + " --resample");
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(has(r, "resampled from 400:700:5")) << r.output;
}

TEST_F(CompareCli, WritesHeatmapAndJsonWithTheVerdict) {
    CliResult r = runCompareCli(f("off.exr") + " " + f("ref.exr") + " --tolerance " + strict + " --heatmap " + f("out/heat.png") +
                    " --json " + f("out/stats.json"));
    EXPECT_EQ(r.code, 1) << r.output;  // files are written whatever the verdict
    auto in = OIIO::ImageInput::open(f("out/heat.png"));
    ASSERT_TRUE(in) << r.output;
    EXPECT_EQ(in->spec().width, 8);
    EXPECT_EQ(in->spec().height, 6);
    in->close();
    std::ifstream js(f("out/stats.json"));
    nlohmann::json j = nlohmann::json::parse(js);
    EXPECT_NEAR(j["max_rel"].get<double>(), 0.005, 1e-6);
    EXPECT_EQ(j["tolerance"]["pass"], false);
    EXPECT_EQ(j["tolerance"]["failures"][0], "max_rel 5e-03 > 1e-03");
    EXPECT_EQ(j["b"], f("ref.exr"));
    EXPECT_TRUE(j.contains("delta_e2000_p95"));
}

TEST_F(CompareCli, ComparesDisplayPngsInCounts) {
    ImageFile png{2, 1, {"R", "G", "B"}, {}};
    writeImage(dir / "a.png", png, std::vector<uint16_t>{10, 20, 30, 40, 50, 60}, 8);
    writeImage(dir / "b.png", png, std::vector<uint16_t>{10, 20, 30, 40, 51, 60}, 8);
    std::string counts = write("counts.json", R"({"max_abs": 1})").string();
    CliResult r = runCompareCli(f("a.png") + " " + f("b.png") + " --tolerance " + counts);
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(has(r, "max abs error     1\n")) << r.output;
    EXPECT_FALSE(has(r, "ΔE2000")) << r.output;
}

TEST_F(CompareCli, MaskLeavesEdgePixelsOutAndQuietPrintsOneLine) {
    SpectralCube ref = smoothCube(8, 6, Grid{400, 700, 10}), edge = ref;
    for (int b = 0; b < ref.bands(); ++b) edge.at(5, 2, b) *= 3.0f;
    writeSpectralExr(dir / "edge.exr", edge);
    std::vector<uint16_t> mask(8 * 6, 0);
    mask[2 * 8 + 5] = 255;
    writeImage(dir / "ref.edges.png", ImageFile{8, 6, {"Y"}, {}}, mask, 8);
    CliResult unmasked = runCompareCli(f("edge.exr") + " " + f("ref.exr") + " -q --tolerance " + strict);
    EXPECT_EQ(unmasked.code, 1) << unmasked.output;
    CliResult masked = runCompareCli(f("edge.exr") + " " + f("ref.exr") + " -q --tolerance " + strict + " --mask " +
                                     f("ref.edges.png"));
    EXPECT_EQ(masked.code, 0) << masked.output;
    EXPECT_TRUE(has(masked, "0 of 47 pixels (1 masked)")) << masked.output;
    EXPECT_EQ(std::count(masked.output.begin(), masked.output.end(), '\n'), 2) << masked.output;  // stats, verdict
}
