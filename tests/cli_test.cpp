// The `metamer` command as a user runs it: exit codes, one-line errors, outputs that appear
// whole or not at all.
#include "color/srgb.h"
#include "io/spectral_exr.h"
#include "support/cli.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;
using namespace metamer;

namespace {

using test::CliRun;

// `metamer ARGS`, with `env` before it.
CliRun run(const std::string& args, const std::string& env = "") { return test::runMetamer(args, {env}); }

fs::path freshDir(const std::string& name) {
    fs::path d = fs::temp_directory_path() / ("metamer-cli-test-" + name);
    fs::remove_all(d);
    return d;
}

const std::string kScene = std::string(METAMER_SOURCE_DIR) + "/tests/data/cli/small.json";

int countLinesStartingWith(const std::string& text, const std::string& prefix) {
    std::istringstream in(text);
    std::string line;
    int n = 0;
    while (std::getline(in, line)) n += line.rfind(prefix, 0) == 0;
    return n;
}

}  // namespace

TEST(Cli, RendersCubeAndQuickLookWithValidationClean) {
    fs::path out = freshDir("render");
    CliRun r = run("render " + kScene + " --out " + out.string() + " --validation --timings");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("W·sr⁻¹·m⁻²·nm⁻¹"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("timings (ms): load"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("validation error"), std::string::npos) << r.output;
    SpectralCube cube = readSpectralExr(out / "small.exr");
    EXPECT_EQ(cube.width, 48);
    EXPECT_EQ(cube.height, 32);
    EXPECT_EQ(cube.bands(), 89);
    EXPECT_TRUE(fs::exists(out / "small.png"));
    // Nothing but the two outputs: no temporary files left behind.
    EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator()), 2);
}

// Files that ordinary tools show right (docs/io.md): the cube's EXR opens in a viewer as the
// display image (R, G, B, A first, BT.709/D65 chromaticities for the sRGB display), the sRGB PNG
// says it is sRGB. Without the PNG, the cube has its bands alone.
TEST(Cli, TheCubeCarriesTheDisplayPreviewAndThePngItsColourSpace) {
    fs::path out = freshDir("preview");
    CliRun r = run("render " + kScene + " --out " + out.string() + " --grid 400:700:10");
    ASSERT_EQ(r.code, 0) << r.output;
    auto exr = OIIO::ImageInput::open((out / "small.exr").string());
    ASSERT_TRUE(exr);
    const OIIO::ImageSpec spec = exr->spec();
    ASSERT_EQ(spec.nchannels, 31 + 4);
    EXPECT_EQ(std::vector<std::string>(spec.channelnames.begin(), spec.channelnames.begin() + 4),
              (std::vector<std::string>{"R", "G", "B", "A"}));
    const OIIO::ParamValue* chroma = spec.find_attribute("chromaticities");
    ASSERT_TRUE(chroma);
    const float* xy = static_cast<const float*>(chroma->data());
    EXPECT_NEAR(xy[0], 0.64, 1e-4);
    EXPECT_NEAR(xy[6], 0.3127, 1e-4);
    std::vector<float> rgba(size_t(spec.width) * spec.height * 4);
    ASSERT_TRUE(exr->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, rgba.data()));
    exr->close();
    auto png = OIIO::ImageInput::open((out / "small.png").string());
    ASSERT_TRUE(png);
    EXPECT_EQ(png->spec().get_string_attribute("oiio:ColorSpace"), "sRGB");
    std::vector<uint8_t> counts(size_t(spec.width) * spec.height * 3);
    ASSERT_TRUE(png->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, counts.data()));
    png->close();
    // The preview is the PNG's counts as linear RGB: encoded, the same counts.
    double worst = 0, lit = 0;
    for (size_t p = 0; p < counts.size() / 3; ++p) {
        EXPECT_EQ(rgba[4 * p + 3], 1.0f);
        for (int c = 0; c < 3; ++c) {
            const double v = std::clamp(double(rgba[4 * p + size_t(c)]), 0.0, 1.0);
            worst = std::max(worst, std::fabs(std::round(255.0 * srgbEncode(v)) - counts[3 * p + size_t(c)]));
            lit = std::max(lit, v);
        }
    }
    EXPECT_EQ(worst, 0.0);
    EXPECT_GT(lit, 0.1);  // not a black image
    // The spectral reader sees the bands alone.
    EXPECT_EQ(readSpectralExr(out / "small.exr").bands(), 31);

    r = run("render " + kScene + " --out " + out.string() + " --grid 400:700:10 --write cube,xyz");
    ASSERT_EQ(r.code, 0) << r.output;
    auto bands = OIIO::ImageInput::open((out / "small.exr").string());
    ASSERT_TRUE(bands);
    EXPECT_EQ(bands->spec().nchannels, 31);
    bands->close();
}

TEST(Cli, GridFlagOverridesTheSceneAndHalfWritesFloat16) {
    fs::path out = freshDir("grid");
    CliRun r = run("render " + kScene + " --out " + out.string() + " --grid 400:700:10 --half --no-png");
    ASSERT_EQ(r.code, 0) << r.output;
    auto in = OIIO::ImageInput::open((out / "small.exr").string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().nchannels, 31);
    EXPECT_EQ(in->spec().format, OIIO::TypeDesc::HALF);
    in->close();
    EXPECT_FALSE(fs::exists(out / "small.png"));
}

TEST(Cli, CpuBackendWritesTheSameLayout) {
    fs::path out = freshDir("cpu");
    CliRun r = run("render " + kScene + " --out " + out.string() + " --backend cpu --no-png");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(readSpectralExr(out / "small.exr").bands(), 89);
}

TEST(Cli, NoVulkanDriverIsOneLineAndExitCode3) {
    fs::path out = freshDir("nodevice");
    CliRun r = run("render " + kScene + " --out " + out.string(), "VK_ICD_FILENAMES=/nonexistent.json");
    EXPECT_EQ(r.code, 3) << r.output;
    EXPECT_EQ(countLinesStartingWith(r.output, "metamer:"), 1) << r.output;
    EXPECT_NE(r.output.find("no usable Vulkan device"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out / "small.exr"));
}

TEST(Cli, DeviceOverrideThatMatchesNothingIsExitCode3) {
    CliRun r = run("render " + kScene + " --out " + freshDir("nomatch").string(), "METAMER_DEVICE=no-such-gpu");
    EXPECT_EQ(r.code, 3) << r.output;
    EXPECT_NE(r.output.find("no-such-gpu"), std::string::npos) << r.output;
}

TEST(Cli, BadInputIsExitCode2WithFileAndKey) {
    CliRun missing = run("render /nonexistent/scene.json --out " + freshDir("missing").string());
    EXPECT_EQ(missing.code, 2) << missing.output;
    EXPECT_NE(missing.output.find("/nonexistent/scene.json"), std::string::npos) << missing.output;

    CliRun grid = run("render " + kScene + " --grid 300:740:7");
    EXPECT_EQ(grid.code, 2) << grid.output;
    EXPECT_NE(grid.output.find("--grid"), std::string::npos) << grid.output;

    CliRun set = run("render " + kScene + " --set materials.skin.diffuse=colorchecker/dark_skn --out " +
                  freshDir("set").string());
    EXPECT_EQ(set.code, 2) << set.output;
    EXPECT_NE(set.output.find("materials.skin.diffuse"), std::string::npos) << set.output;
    EXPECT_NE(set.output.find("did you mean"), std::string::npos) << set.output;

    CliRun strict = run("render " + kScene + " --strict-coverage --out " + freshDir("strict").string());
    EXPECT_EQ(strict.code, 2) << strict.output;
    EXPECT_NE(strict.output.find("covers 380–780 nm"), std::string::npos) << strict.output;
}

TEST(Cli, FailedRenderLeavesThePreviousCubeIntact) {
    fs::path out = freshDir("intact");
    ASSERT_EQ(run("render " + kScene + " --out " + out.string() + " --no-png").code, 0);
    auto read = [](const fs::path& p) {
        std::ifstream f(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), {});
    };
    std::string before = read(out / "small.exr");
    CliRun r = run("render " + kScene + " --out " + out.string() + " --set camera.width=-5");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_EQ(read(out / "small.exr"), before);
    EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator()), 1);
}

TEST(Cli, DisplayPathWritesPngXyzAndResponses) {
    fs::path out = freshDir("display");
    CliRun r = run("render " + kScene + " --out " + out.string() +
                   " --detector camera:nikon_d5100 --adapt cat16 --display crt --bits 16 --write png,xyz,responses");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("camera characterization: rms ΔE2000"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out / "small.exr"));  // not asked for
    auto png = OIIO::ImageInput::open((out / "small.png").string());
    ASSERT_TRUE(png);
    EXPECT_EQ(png->spec().format, OIIO::TypeDesc::UINT16);
    EXPECT_NE(png->spec().get_string_attribute("ImageDescription").find("adaptation cat16"), std::string::npos);
    // The CRT's PNG carries its ICC profile (color/display_profile). (OpenImageIO calls every PNG
    // without a gAMA chunk sRGB, so the absence of the sRGB chunk is checked by
    // tests/python/check_ordinary_tools.py, which reads the chunks.)
    const OIIO::ParamValue* icc = png->spec().find_attribute("ICCProfile");
    ASSERT_TRUE(icc);
    EXPECT_GT(icc->type().size(), 128u);
    EXPECT_EQ(std::string(static_cast<const char*>(icc->data()) + 36, 4), "acsp");  // the ICC signature
    png->close();
    // XYZ in R, G, B with OpenEXR's XYZ chromaticities.
    auto xyz = OIIO::ImageInput::open((out / "small.xyz.exr").string());
    ASSERT_TRUE(xyz);
    EXPECT_EQ(xyz->spec().channelnames, (std::vector<std::string>{"R", "G", "B"}));
    const OIIO::ParamValue* chroma = xyz->spec().find_attribute("chromaticities");
    ASSERT_TRUE(chroma);
    const float* xy = static_cast<const float*>(chroma->data());
    EXPECT_EQ(std::vector<float>(xy, xy + 8), (std::vector<float>{1, 0, 0, 1, 0, 0, 1.0f / 3, 1.0f / 3}));
    EXPECT_NE(xyz->spec().get_string_attribute("metamer:xyz").find("Y = 100"), std::string::npos);
    xyz->close();
    auto resp = OIIO::ImageInput::open((out / "small.camera-nikon_d5100.exr").string());
    ASSERT_TRUE(resp);
    EXPECT_EQ(resp->spec().nchannels, 3);
    resp->close();
}

// Display outputs alone take the response pass (no band is drawn); with the cube the band passes
// run and the PNG is computed from them (docs/color.md, "The response pass").
TEST(Cli, DisplayOutputsAloneTakeTheResponsePassAndTheCubeTheBands) {
    fs::path out = freshDir("response-pass");
    CliRun r = run("render " + kScene + " --out " + out.string() + " --write png,xyz -v");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("response pass: 3 detector channel(s)"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find(" bands in "), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out / "small.exr"));
    r = run("render " + kScene + " --out " + out.string() + " --write cube,png -v");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(r.output.find("response pass"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(" bands in "), std::string::npos) << r.output;
    EXPECT_TRUE(fs::exists(out / "small.exr"));
    EXPECT_TRUE(fs::exists(out / "small.png"));
}

TEST(Cli, CustomCsvDetectorWritesItsChannels) {
    fs::path out = freshDir("csvdetector");
    fs::create_directories(out);
    {
        std::ofstream f(out / "uv.csv");
        f << "wavelength_nm,uva,blue\n300,1,0\n400,1,0\n401,0,1\n500,0,1\n";
    }
    CliRun r = run("render " + kScene + " --out " + out.string() + " --detector csv:" + (out / "uv.csv").string() +
                   " --write responses,png");
    ASSERT_EQ(r.code, 0) << r.output;
    auto resp = OIIO::ImageInput::open((out / "small.csv-uv.exr").string());
    ASSERT_TRUE(resp) << r.output;
    // OpenEXR stores channels sorted by name.
    EXPECT_EQ(resp->spec().channelnames, (std::vector<std::string>{"blue", "uva"}));
    resp->close();
    EXPECT_NE(r.output.find("has no display path"), std::string::npos) << r.output;
}

TEST(Cli, DisplayPathErrorsNameTheFlagOrTheSceneKey) {
    CliRun adapt = run("render " + kScene + " --adapt bradfrod --out " + freshDir("adapt").string());
    EXPECT_EQ(adapt.code, 2) << adapt.output;
    EXPECT_NE(adapt.output.find("--adapt"), std::string::npos) << adapt.output;
    EXPECT_NE(adapt.output.find("bradford"), std::string::npos) << adapt.output;

    CliRun detector = run("render " + kScene + " --detector camera:nikon --out " + freshDir("det").string());
    EXPECT_EQ(detector.code, 2) << detector.output;
    EXPECT_NE(detector.output.find("--detector"), std::string::npos) << detector.output;

    CliRun scene = run("render " + kScene + " --set output={\\\"detector\\\":\\\"cie1913\\\"} --out " +
                       freshDir("scenedet").string());
    EXPECT_EQ(scene.code, 2) << scene.output;
    EXPECT_NE(scene.output.find("small.json: output.detector"), std::string::npos) << scene.output;

    CliRun absolute = run("render " + kScene + " --detector cie1964 --xyz absolute --out " + freshDir("abs").string());
    EXPECT_EQ(absolute.code, 2) << absolute.output;
    EXPECT_NE(absolute.output.find("CIE 1931"), std::string::npos) << absolute.output;
}

TEST(Cli, ImagesOverTheMemoryBudgetAreRenderedInStripsWithTheSameResult) {
    fs::path whole = freshDir("budget-whole"), strips = freshDir("budget-strips");
    std::string args = "render " + kScene + " --write cube,png,xyz --set camera.width=96 --set camera.height=80 --out ";
    ASSERT_EQ(run(args + whole.string()).code, 0);
    CliRun r = run(args + strips.string() + " --memory-budget 1");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("strips of"), std::string::npos) << r.output;
    // Same values (float rounding aside), same display counts.
    SpectralCube a = readSpectralExr(strips / "small.exr"), b = readSpectralExr(whole / "small.exr");
    ASSERT_EQ(a.data.size(), b.data.size());
    double worst = 0;
    for (size_t i = 0; i < a.data.size(); ++i)
        worst = std::max(worst, double(std::fabs(a.data[i] - b.data[i])) / std::max(1e-6, double(std::fabs(b.data[i]))));
    EXPECT_LT(worst, 1e-3);
    // Display counts: the strip projection rounds differently in the last float bit, which may move
    // a pixel on a count boundary by one.
    {
        std::ofstream tol(strips.parent_path() / "metamer-budget-one-count.json");
        tol << R"({"description": "strips vs whole frame", "max_abs": 1})";
    }
    CliRun png = run("compare " + (strips / "small.png").string() + " " + (whole / "small.png").string() +
                     " -q --tolerance " + (strips.parent_path() / "metamer-budget-one-count.json").string());
    EXPECT_EQ(png.code, 0) << png.output;
    // No temporary file left behind.
    EXPECT_EQ(std::distance(fs::directory_iterator(strips), fs::directory_iterator()), 3);

    CliRun cpu = run(args + freshDir("budget-cpu").string() + " --memory-budget 1 --backend cpu");
    EXPECT_EQ(cpu.code, 2) << cpu.output;
    EXPECT_NE(cpu.output.find("--memory-budget"), std::string::npos) << cpu.output;
    EXPECT_NE(cpu.output.find("MiB"), std::string::npos) << cpu.output;
}

// Issue 19, class 3 (engine/app/cli_checks.h): values refused when parsed, with the option's name.
TEST(CliChecks, UnknownVerbsSuggestTheNearestAndHelpForThemIsAnError) {
    CliRun typo = run("rendr " + kScene);
    EXPECT_EQ(typo.code, 2) << typo.output;
    EXPECT_NE(typo.output.find("'rendr' is not a command (did you mean 'render'?)"), std::string::npos) << typo.output;
    CliRun help = run("batchx --help");
    EXPECT_EQ(help.code, 2) << help.output;
    EXPECT_NE(help.output.find("'batchx' is not a command (did you mean 'batch'?)"), std::string::npos) << help.output;
    EXPECT_EQ(countLinesStartingWith(help.output, "metamer: "), 1) << help.output;
    CliRun far = run("zzzzzz");
    EXPECT_EQ(far.code, 2) << far.output;
    EXPECT_EQ(far.output.find("did you mean"), std::string::npos) << far.output;
}

TEST(CliChecks, EmptyAndNonFiniteValuesNameTheOption) {
    const fs::path out = freshDir("empty-out");
    CliRun emptyOut = run("render " + kScene + " --out ''");
    EXPECT_EQ(emptyOut.code, 2) << emptyOut.output;
    EXPECT_NE(emptyOut.output.find("--out: expected a value, got an empty string"), std::string::npos) << emptyOut.output;
    EXPECT_FALSE(fs::exists(fs::path(kScene).parent_path() / "small.exr"));
    CliRun threshold = run("compare a.exr b.exr --pixel-threshold nan");
    EXPECT_EQ(threshold.code, 2) << threshold.output;
    EXPECT_NE(threshold.output.find("--pixel-threshold"), std::string::npos) << threshold.output;
    CliRun negative = run("compare a.exr b.exr --relative-floor -1");
    EXPECT_EQ(negative.code, 2) << negative.output;
    EXPECT_NE(negative.output.find("'-1': expected a number of 0 or more"), std::string::npos) << negative.output;
    EXPECT_EQ(negative.output.find("1.797"), std::string::npos) << negative.output;
}

TEST(CliChecks, AnUnreadableSpectraLibraryNamesTheVariable) {
    CliRun r = run("render " + kScene + " --out " + freshDir("no-library").string(), "METAMER_SPECTRA=/nonexistent/spectra");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("METAMER_SPECTRA: spectra library '/nonexistent/spectra' not found"), std::string::npos)
        << r.output;
}

TEST(CliChecks, CountsOf8And16BitImagesAreNotCompared) {
    const fs::path d8 = freshDir("counts-8"), d16 = freshDir("counts-16");
    ASSERT_EQ(run("render " + kScene + " --write png --bits 8 --out " + d8.string()).code, 0);
    ASSERT_EQ(run("render " + kScene + " --write png --bits 16 --out " + d16.string()).code, 0);
    CliRun r = run("compare " + (d8 / "small.png").string() + " " + (d16 / "small.png").string());
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("png 8-bit counts but the reference"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("counts on different scales"), std::string::npos) << r.output;
    // Two 8-bit formats are on one scale: a PNG and a JPEG of it compare (a JPEG's error is small).
    ASSERT_EQ(std::system(("oiiotool " + (d8 / "small.png").string() + " --quality 100 -o " +
                           (d8 / "small.jpg").string()).c_str()), 0);
    CliRun formats = run("compare " + (d8 / "small.jpg").string() + " " + (d8 / "small.png").string());
    EXPECT_NE(formats.code, 2) << formats.output;
    EXPECT_EQ(formats.output.find("different scales"), std::string::npos) << formats.output;
}

// Issue 19, class 2: a run replaces all its outputs or none, and targets that cannot work are
// found before the render.
TEST(CliOutputs, ATargetThatCannotBeWrittenFailsBeforeTheRenderAndKeepsThePreviousSet) {
    const fs::path out = freshDir("all-or-none");
    ASSERT_EQ(run("render " + kScene + " --write cube,png --out " + out.string()).code, 0);
    auto read = [](const fs::path& p) {
        std::ifstream f(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), {});
    };
    const std::string cube = read(out / "small.exr"), png = read(out / "small.png");
    fs::create_directories(out / "small.xyz.exr");  // the third output's name is taken by a folder
    CliRun r = run("render " + kScene + " --write cube,png,xyz --set lights.1.scale=0.02 --out " + out.string());
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("small.xyz.exr': it is a folder"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("wrote"), std::string::npos) << r.output;
    EXPECT_EQ(countLinesStartingWith(r.output, "metamer: "), 1) << r.output;
    EXPECT_EQ(read(out / "small.exr"), cube);
    EXPECT_EQ(read(out / "small.png"), png);
    EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator()), 3);  // no temporaries
}

TEST(CliOutputs, AnOutFolderThatIsAFileOrADeviceIsAnInputError) {
    const fs::path dir = freshDir("out-is-a-file");
    fs::create_directories(dir);
    std::ofstream(dir / "notes.txt") << "mine";
    for (const std::string& args : {"render " + kScene, "bench " + kScene, "preview " + kScene, std::string("batch sweep.json")}) {
        CliRun file = run(args + " --out " + (dir / "notes.txt").string());
        EXPECT_EQ(file.code, 2) << args << "\n" << file.output;
        EXPECT_NE(file.output.find("--out: '" + (dir / "notes.txt").string() + "' is a file, not a folder"),
                  std::string::npos) << file.output;
    }
    CliRun device = run("render " + kScene + " --out /dev/full");
    EXPECT_EQ(device.code, 2) << device.output;
    EXPECT_NE(device.output.find("'/dev/full' is a character device, not a folder"), std::string::npos) << device.output;
    // A pseudo file system takes no files: found when the outputs are opened, before the render.
    CliRun proc = run("render " + kScene + " --out /proc/metamer-out");
    EXPECT_EQ(proc.code, 1) << proc.output;
    EXPECT_NE(proc.output.find("/proc/metamer-out"), std::string::npos) << proc.output;
    EXPECT_EQ(proc.output.find("wrote"), std::string::npos) << proc.output;
    std::ifstream in(dir / "notes.txt");
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "mine");
}

// A disk that fills during the run: the write fails (exit 1), the previous files stay and no
// temporary file is left. Needs a small tmpfs, so root (CI runs as root); skipped otherwise.
TEST(CliOutputs, AFullDiskFailsTheRunAndKeepsThePreviousSet) {
    const fs::path mount = freshDir("full-disk");
    fs::create_directories(mount);
    if (std::system(("mount -t tmpfs -o size=200k tmpfs " + mount.string() + " 2>/dev/null").c_str()) != 0)
        GTEST_SKIP() << "cannot mount a tmpfs here (not root?)";
    struct Unmount {
        fs::path at;
        ~Unmount() { std::system(("umount " + at.string()).c_str()); }
    } unmount{mount};
    const fs::path out = mount / "o";
    ASSERT_EQ(run("render " + kScene + " --write png --out " + out.string()).code, 0);
    std::ifstream in(out / "small.png", std::ios::binary);
    const std::string png(std::istreambuf_iterator<char>(in), {});
    // A 200 × 200 cube of 89 bands does not fit in 200 KiB.
    CliRun r = run("render " + kScene + " --write cube,png,xyz --set camera.width=200 --set camera.height=200 --out " +
                   out.string());
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("No space left on device"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find(".tmp-"), std::string::npos) << r.output;  // the file asked for, not its temporary
    std::ifstream again(out / "small.png", std::ios::binary);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(again), {}), png);
    EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator()), 1);
}

// Options that change only files the run does not write are said (class 3, "meaningful together").
TEST(CliChecks, OptionsForFilesNotWrittenAreSaid) {
    const fs::path out = freshDir("no-effect");
    CliRun half = run("render " + kScene + " --half --format hdf5 --bits 16 --write cube --out " + out.string());
    EXPECT_EQ(half.code, 0) << half.output;
    EXPECT_NE(half.output.find("--half: has no effect"), std::string::npos) << half.output;
    EXPECT_NE(half.output.find("--bits: 16 has no effect"), std::string::npos) << half.output;
    CliRun compression = run("render " + kScene + " --compression zip --write png --out " + out.string());
    EXPECT_NE(compression.output.find("--compression: 'zip' has no effect"), std::string::npos) << compression.output;
    CliRun fine = run("render " + kScene + " --half --compression zip --bits 16 --out " + out.string());
    EXPECT_EQ(fine.output.find("has no effect"), std::string::npos) << fine.output;
}

// Issue 35, item 5: the threads come from what the scheduler gave, observable with -v.
namespace {
// The variables these tests set, unset first so that the machine's own do not leak in.
const std::string kClean = "env -u LP_NUM_THREADS -u SLURM_CPUS_PER_TASK -u METAMER_DEVICE -u CUDA_VISIBLE_DEVICES "
                           "-u SLURM_LOCALID ";
}  // namespace

TEST(CliThreads, TasksetToOneCpuGivesOneThread) {
    CliRun r = run("render " + kScene + " -v --out " + freshDir("taskset").string(), kClean + "taskset -c 0");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("threads: 1 (sched_getaffinity (1 CPU this process may run on))"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("LP_NUM_THREADS=1 (from sched_getaffinity"), std::string::npos) << r.output;
}

TEST(CliThreads, SlurmCpusPerTaskIsHonouredWithinTheAffinity) {
    CliRun one = run("render " + kScene + " -v --out " + freshDir("slurm-1").string(), kClean + "SLURM_CPUS_PER_TASK=1");
    ASSERT_EQ(one.code, 0) << one.output;
    EXPECT_NE(one.output.find("threads: 1 (SLURM_CPUS_PER_TASK)"), std::string::npos) << one.output;
    EXPECT_NE(one.output.find("LP_NUM_THREADS=1"), std::string::npos) << one.output;
    CliRun many = run("render " + kScene + " -v --out " + freshDir("slurm-many").string(),
                      kClean + "taskset -c 0 env SLURM_CPUS_PER_TASK=64");
    ASSERT_EQ(many.code, 0) << many.output;
    EXPECT_NE(many.output.find("threads: 1 (SLURM_CPUS_PER_TASK=64, bounded by sched_getaffinity (1 CPU))"),
              std::string::npos) << many.output;
    CliRun flag = run("render " + kScene + " -v --threads 3 --out " + freshDir("flag").string(),
                      kClean + "SLURM_CPUS_PER_TASK=1 LP_NUM_THREADS=2");
    ASSERT_EQ(flag.code, 0) << flag.output;
    EXPECT_NE(flag.output.find("threads: 3 (--threads)"), std::string::npos) << flag.output;
    EXPECT_NE(flag.output.find("LP_NUM_THREADS=2 (set by the user)"), std::string::npos) << flag.output;
    CliRun bad = run("render " + kScene + " --out " + freshDir("slurm-bad").string(), kClean + "SLURM_CPUS_PER_TASK=all");
    EXPECT_EQ(bad.code, 2) << bad.output;
    EXPECT_NE(bad.output.find("SLURM_CPUS_PER_TASK: 'all' is not a thread count"), std::string::npos) << bad.output;
    CliRun zero = run("batch sweep.json --threads 0");
    EXPECT_EQ(zero.code, 2) << zero.output;
    EXPECT_NE(zero.output.find("--threads: '0' is not a thread count"), std::string::npos) << zero.output;
}

// Issue 35, item 4: -o names the output file, a folder stays a folder, the rest is an error.
TEST(CliOutputName, AFileNameNamesEveryOutput) {
    const fs::path d = freshDir("named");
    CliRun r = run("render " + kScene + " -o " + (d / "x.exr").string());
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(readSpectralExr(d / "x.exr").bands(), 89);
    EXPECT_TRUE(fs::exists(d / "x.png"));
    EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator()), 2);
    CliRun h5 = run("render " + kScene + " --no-png -o " + (d / "y.h5").string());
    ASSERT_EQ(h5.code, 0) << h5.output;
    EXPECT_TRUE(fs::exists(d / "y.h5"));
    EXPECT_FALSE(fs::exists(d / "y.exr"));
    CliRun png = run("render " + kScene + " --write png --output " + (d / "z.png").string());
    ASSERT_EQ(png.code, 0) << png.output;
    EXPECT_TRUE(fs::exists(d / "z.png"));
    EXPECT_FALSE(fs::exists(d / "z.exr"));
}

TEST(CliOutputName, AFolderStaysAFolder) {
    const fs::path d = freshDir("slash");
    CliRun r = run("render " + kScene + " -o " + (d / "result.exr").string() + "/");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::is_directory(d / "result.exr"));
    EXPECT_TRUE(fs::exists(d / "result.exr" / "small.exr"));
    // An existing folder with an output's extension is a folder too.
    CliRun again = run("render " + kScene + " --no-png -o " + (d / "result.exr").string());
    ASSERT_EQ(again.code, 0) << again.output;
    EXPECT_TRUE(fs::is_directory(d / "result.exr"));
}

// Issue 46: a folder's name may hold dots; only an output's extension or a refused one names a file.
TEST(CliOutputName, ANameWithADotIsAFolder) {
    const fs::path d = freshDir("dotted");
    CliRun r = run("render " + std::string(METAMER_SOURCE_DIR) + "/scenes/colorchecker.json --out " +
                   (d / "runs" / "v1.2").string());
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::is_directory(d / "runs" / "v1.2"));
    EXPECT_TRUE(fs::exists(d / "runs" / "v1.2" / "colorchecker.exr"));
    EXPECT_TRUE(fs::exists(d / "runs" / "v1.2" / "colorchecker.png"));
    EXPECT_EQ(std::distance(fs::directory_iterator(d / "runs"), fs::directory_iterator()), 1);  // no runs/v1.exr
    // A relative name, from the folder the user is in.
    test::CliOptions here;
    here.dir = d.string();
    CliRun dated = test::runMetamer("render " + kScene + " --no-png -o 2026.12.05", here);
    ASSERT_EQ(dated.code, 0) << dated.output;
    EXPECT_TRUE(fs::exists(d / "2026.12.05" / "small.exr"));
}

TEST(CliOutputName, RefusedOrUnwrittenNamesAreErrors) {
    const fs::path d = freshDir("refused");
    CliRun tiff = run("render " + kScene + " -o " + (d / "result.tiff").string());
    EXPECT_EQ(tiff.code, 2) << tiff.output;
    EXPECT_NE(tiff.output.find("--out: '" + (d / "result.tiff").string() + "' names a .tiff file, which Metamer does not "
                               "write"), std::string::npos) << tiff.output;
    EXPECT_NE(tiff.output.find("Metamer writes NAME.exr, NAME.h5, NAME.mat, NAME.hdr or NAME.png"), std::string::npos) << tiff.output;
    CliRun jpeg = run("render " + kScene + " -o " + (d / "result.JPEG").string());
    EXPECT_EQ(jpeg.code, 2) << jpeg.output;
    EXPECT_NE(jpeg.output.find("names a .JPEG file"), std::string::npos) << jpeg.output;
    CliRun hdf5 = run("render " + kScene + " -o " + (d / "cube.hdf5").string());
    EXPECT_EQ(hdf5.code, 2) << hdf5.output;
    EXPECT_NE(hdf5.output.find("names a .hdf5 file: HDF5 cubes are NAME.h5"), std::string::npos) << hdf5.output;
    CliRun upper = run("render " + kScene + " -o " + (d / "X.EXR").string());
    EXPECT_EQ(upper.code, 2) << upper.output;
    EXPECT_NE(upper.output.find("output files are named in lower case; write '" + (d / "X.exr").string() + "'"),
              std::string::npos) << upper.output;
    CliRun clash = run("render " + kScene + " --format exr -o " + (d / "x.h5").string());
    EXPECT_EQ(clash.code, 2) << clash.output;
    EXPECT_NE(clash.output.find("--out: '"), std::string::npos) << clash.output;
    EXPECT_NE(clash.output.find("names a cube in hdf5 format, but --format asks for exr"), std::string::npos)
        << clash.output;
    CliRun noPng = run("render " + kScene + " --no-png -o " + (d / "x.png").string());
    EXPECT_EQ(noPng.code, 2) << noPng.output;
    EXPECT_NE(noPng.output.find("names the display PNG, which this run does not write"), std::string::npos)
        << noPng.output;
    EXPECT_FALSE(fs::exists(d));  // nothing made
}

TEST(CliOutputName, ASceneFromStdinResolvesItsPathsAgainstTheCurrentFolder) {
    const fs::path d = freshDir("stdin");
    fs::create_directories(d / "elsewhere");
    fs::copy_file(fs::path(METAMER_SOURCE_DIR) / "spectra" / "illuminants" / "A.csv", d / "mine.csv");
    std::ifstream in(kScene);
    std::string text(std::istreambuf_iterator<char>(in), {});
    const std::string from = "\"illuminants/A\"";
    text.replace(text.find(from), from.size(), "\"mine.csv\"");
    std::ofstream(d / "scene.txt") << text;
    test::CliOptions here;
    here.dir = d.string();
    CliRun r = test::runMetamer("render - -o out/ < scene.txt", here);
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::exists(d / "out" / "stdin.exr"));
    CliRun named = test::runMetamer("render - --no-png -o lamp.exr < scene.txt", here);
    ASSERT_EQ(named.code, 0) << named.output;
    EXPECT_TRUE(fs::exists(d / "lamp.exr"));
    test::CliOptions there;
    there.dir = (d / "elsewhere").string();
    CliRun missing = test::runMetamer("render - -o out/ < ../scene.txt", there);
    EXPECT_EQ(missing.code, 2) << missing.output;
    EXPECT_NE(missing.output.find("<stdin>"), std::string::npos) << missing.output;
    EXPECT_NE(missing.output.find("mine.csv"), std::string::npos) << missing.output;
}

TEST(CliOptions, AMistypedOptionGetsTheNearestOne) {
    CliRun r = run("render " + kScene + " --outptu x.exr");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("--outptu: not an option of metamer render (did you mean --output?)"), std::string::npos)
        << r.output;
    EXPECT_EQ(countLinesStartingWith(r.output, "metamer: "), 1) << r.output;
    CliRun batch = run("batch sweep.json --shrad 0/2");
    EXPECT_EQ(batch.code, 2) << batch.output;
    EXPECT_NE(batch.output.find("(did you mean --shard?)"), std::string::npos) << batch.output;
    CliRun far = run("render " + kScene + " --zzzzzzzz");
    EXPECT_EQ(far.code, 2) << far.output;
    EXPECT_EQ(far.output.find("did you mean"), std::string::npos) << far.output;
}

// Issue 35, item 1: progress on stderr when asked (tests run without a terminal), -q silent.
TEST(CliProgress, PrintedWithProgressAndNotWithoutATerminal) {
    const std::string strips = " --memory-budget 0.5 --out " + freshDir("progress").string();
    test::CliOptions errors;
    errors.stderrOnly = true;
    CliRun asked = test::runMetamer("render " + kScene + strips + " --progress", errors);
    ASSERT_EQ(asked.code, 0) << asked.output;
    EXPECT_NE(asked.output.find("metamer: rendering: "), std::string::npos) << asked.output;
    EXPECT_NE(asked.output.find("metamer: strip 1 of "), std::string::npos) << asked.output;
    EXPECT_NE(asked.output.find(" left"), std::string::npos) << asked.output;
    EXPECT_EQ(asked.output.find('\r'), std::string::npos) << "not a terminal: one line per step";
    CliRun unasked = test::runMetamer("render " + kScene + strips, errors);
    ASSERT_EQ(unasked.code, 0) << unasked.output;
    EXPECT_EQ(unasked.output.find("metamer: "), std::string::npos) << unasked.output;
}

TEST(CliProgress, QuietPrintsNothingButErrors) {
    CliRun quiet = run("render " + kScene + " -q --no-png --half --out " + freshDir("quiet").string());
    EXPECT_EQ(quiet.code, 0) << quiet.output;
    EXPECT_EQ(quiet.output, "");  // not even the --half warning or the "wrote" lines
    CliRun error = run("render /nonexistent.json -q");
    EXPECT_EQ(error.code, 2);
    EXPECT_EQ(countLinesStartingWith(error.output, "metamer: "), 1) << error.output;
    CliRun both = run("render " + kScene + " -q -v");
    EXPECT_EQ(both.code, 2) << both.output;
}

// Issue 35, item 5: the Vulkan device from METAMER_DEVICE, CUDA_VISIBLE_DEVICES, SLURM_LOCALID
// (lavapipe is the one device here).
TEST(CliDevices, TheVariablesChooseAndWhatMatchesNothingIsAClearError) {
    const std::string out = " --no-png -v --out " + freshDir("devices").string();
    CliRun zero = run("render " + kScene + out, kClean + "METAMER_DEVICE=0");
    ASSERT_EQ(zero.code, 0) << zero.output;
    EXPECT_NE(zero.output.find("chosen by METAMER_DEVICE=0"), std::string::npos) << zero.output;
    CliRun five = run("render " + kScene + out, kClean + "METAMER_DEVICE=5");
    EXPECT_EQ(five.code, 3) << five.output;
    EXPECT_NE(five.output.find("METAMER_DEVICE='5' is not a device index; the devices: 0: llvmpipe"), std::string::npos)
        << five.output;
    CliRun uuid = run("render " + kScene + out, kClean + "METAMER_DEVICE=GPU-00000000-1111-2222-3333-444444444444");
    EXPECT_EQ(uuid.code, 3) << uuid.output;
    EXPECT_NE(uuid.output.find("is not the UUID of any Vulkan device"), std::string::npos) << uuid.output;
    CliRun cuda = run("render " + kScene + out, kClean + "CUDA_VISIBLE_DEVICES=GPU-00000000-1111-2222-3333-444444444444");
    EXPECT_EQ(cuda.code, 3) << cuda.output;
    EXPECT_NE(cuda.output.find("CUDA_VISIBLE_DEVICES='GPU-00000000"), std::string::npos) << cuda.output;
    CliRun cudaIndex = run("render " + kScene + out, kClean + "CUDA_VISIBLE_DEVICES=0");
    ASSERT_EQ(cudaIndex.code, 0) << cudaIndex.output;
    EXPECT_NE(cudaIndex.output.find("chosen by CUDA_VISIBLE_DEVICES=0"), std::string::npos) << cudaIndex.output;
    CliRun local = run("render " + kScene + out, kClean + "SLURM_LOCALID=3");
    ASSERT_EQ(local.code, 0) << local.output;
    EXPECT_NE(local.output.find("chosen by SLURM_LOCALID=3 (of 1 GPU)"), std::string::npos) << local.output;
    CliRun list = run("devices", kClean);
    ASSERT_EQ(list.code, 0) << list.output;
    EXPECT_NE(list.output.find(" UUID "), std::string::npos) << list.output;
    EXPECT_NE(list.output.find("a render uses 0 (the best score)"), std::string::npos) << list.output;
}

// docs/cli.md's reference is what `metamer --markdown-reference` prints from the declarations.
TEST(CliReference, DocsAreCurrent) {
    CliRun r = run("--markdown-reference");
    ASSERT_EQ(r.code, 0) << r.output;
    std::ifstream in(std::string(METAMER_SOURCE_DIR) + "/docs/cli.md");
    const std::string doc(std::istreambuf_iterator<char>(in), {});
    const std::string begin = "<!-- begin: generated by metamer --markdown-reference -->";
    const std::string end = "<!-- end: generated by metamer --markdown-reference -->\n";
    const size_t a = doc.find(begin), b = doc.find(end);
    ASSERT_NE(a, std::string::npos) << "docs/cli.md has no reference block";
    ASSERT_NE(b, std::string::npos) << "docs/cli.md has no reference block";
    EXPECT_EQ(doc.substr(a, b + end.size() - a), r.output)
        << "docs/cli.md is stale: python3 tools/update_cli_reference.py build/metamer";
}

// Issue 51, class 8, and issue 50: coloured shadows cost the transparent area each light sees × the
// optical-depth channels' layers (render/transmittance_map_cost.h: per transparent material, not
// per band). 50 000 sheets each covering the light's whole view, cycling through 64 filters (16
// layers), would take about 12 minutes of transmittance maps with lavapipe: refused before anything
// is drawn, naming the count and the time. The CPU reference traces shadow rays instead.
TEST(Cli, ColouredShadowsThatWouldTakeTooLongAreRefusedBeforeDrawing) {
    const fs::path dir = freshDir("transmittance-cost");
    fs::create_directories(dir);
    std::string objects = R"({"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [2, 2], "material": "back"})";
    std::string materials = R"("back": {"diffuse": 0.5})";
    for (int m = 0; m < 64; ++m) materials += fmt::format(R"(, "f{}": {{"transmittance": {}}})", m, 0.9 - 0.001 * m);
    for (int i = 0; i < 50000; ++i)
        objects += fmt::format(R"(, {{"shape": "quad", "center": [0, 0, {}], "normal": [0, 0, 1], "size": [2, 2], "material": "f{}"}})",
                               0.1 + 1e-5 * i, i % 64);
    std::ofstream(dir / "nested.json") << R"({"grid": {"start_nm": 380, "end_nm": 780, "step_nm": 5},
  "camera": {"position": [0, 0, 30], "target": [0, 0, 0], "width": 8, "height": 8},
  "lights": [{"type": "directional", "direction": [0, 0, -1], "spectrum": "illuminants/D65", "scale": 0.01}],
  "materials": {)" << materials << R"(},
  "objects": [)" << objects << "]}";
    const CliRun gpu = run("render " + (dir / "nested.json").string() + " --out " + (dir / "gpu").string());
    EXPECT_EQ(gpu.code, 2) << gpu.output;
    EXPECT_NE(gpu.output.find("nested.json: lights: coloured shadows: 50000 transparent objects drawn into 1 light map "
                              "layer(s) of 16 optical-depth layer(s)"),
              std::string::npos)
        << gpu.output;
    EXPECT_NE(gpu.output.find("more than the 600 s a scene's transmittance maps may take"), std::string::npos)
        << gpu.output;
    EXPECT_TRUE(!fs::exists(dir / "gpu") || fs::is_empty(dir / "gpu"));  // nothing written
    const CliRun cpu = run("render " + (dir / "nested.json").string() + " --out " + (dir / "cpu").string() +
                           " --backend cpu --write cube");
    EXPECT_EQ(cpu.code, 0) << cpu.output;
    fs::remove_all(dir);
}

// Issue 50: the coloured shadows' maps carry one optical-depth channel per sheet or medium material
// and two per slab, at most MAX_DEPTH_CHANNELS (64): 65 filter materials under a shadow-casting
// light are refused before anything is drawn, with the counts and what to change; without the
// light's shadows the same scene renders (the camera's own transmission has no such limit).
TEST(Cli, MoreOpticalDepthChannelsThanTheMapsCarryAreRefused) {
    const fs::path dir = freshDir("depth-channels");
    fs::create_directories(dir);
    std::string objects = R"({"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [2, 2], "material": "back"})";
    std::string materials = R"("back": {"diffuse": 0.5})";
    for (int m = 0; m < 65; ++m) {
        materials += fmt::format(R"(, "f{}": {{"transmittance": {}}})", m, 0.95 - 0.001 * m);
        objects += fmt::format(R"(, {{"shape": "quad", "center": [0, 0, {}], "normal": [0, 0, 1], "size": [0.5, 0.5], "material": "f{}"}})",
                               0.1 + 0.001 * m, m);
    }
    std::ofstream(dir / "many.json") << R"({"grid": {"start_nm": 400, "end_nm": 700, "step_nm": 10},
  "camera": {"position": [0, 0, 5], "target": [0, 0, 0], "width": 8, "height": 8},
  "lights": [{"type": "directional", "direction": [0.2, 0, -1], "spectrum": "illuminants/D65", "scale": 0.01}],
  "materials": {)" << materials << R"(},
  "objects": [)" << objects << "]}";
    const CliRun refused = run("render " + (dir / "many.json").string() + " --out " + (dir / "gpu").string());
    EXPECT_EQ(refused.code, 2) << refused.output;
    EXPECT_NE(refused.output.find("many.json: materials: 65 transparent materials cast coloured shadows (65 sheets and "
                                  "media, one optical-depth channel each, and 0 slabs, two each: 65 channels); at most 64"),
              std::string::npos)
        << refused.output;
    EXPECT_TRUE(!fs::exists(dir / "gpu") || fs::is_empty(dir / "gpu"));
    const CliRun unshadowed = run("render " + (dir / "many.json").string() + " --out " + (dir / "plain").string() +
                                  " --set lights.0.shadows=false --write cube");
    EXPECT_EQ(unshadowed.code, 0) << unshadowed.output;
    fs::remove_all(dir);
}
