#include "io/spectral_exr.h"

#include "io/atomic_file.h"

#include "support/cubes.h"
#include "support/temp_folder.h"

#include <OpenImageIO/imageio.h>
#include <OpenEXR/ImfThreading.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <thread>
#include <unistd.h>

using namespace metamer;
namespace fs = std::filesystem;
using test::expectBitExact;
using test::randomCube;
using test::slurp;

namespace {

class SpectralExr : public test::TempFolderTest {
protected:
    // Files in the folder other than `keep`: temporary leftovers.
    std::vector<std::string> othersThan(const fs::path& keep) const {
        std::vector<std::string> found;
        for (const auto& name : namesIn())
            if (dir / name != keep) found.push_back(name);
        return found;
    }
};

}  // namespace

TEST_F(SpectralExr, ChannelNamesUseCommaDecimalsAndSixPlaces) {
    EXPECT_EQ(spectralChannelName(300.0), "S0.300,000000nm");
    EXPECT_EQ(spectralChannelName(552.5), "S0.552,500000nm");
    EXPECT_EQ(spectralChannelName(1000.0), "S0.1000,000000nm");
}

TEST_F(SpectralExr, Float32RoundTripIsBitExact) {
    SpectralCube cube = randomCube(7, 5, Grid{300, 740, 5}, 1);
    ASSERT_EQ(cube.bands(), 89);
    fs::path file = dir / "cube.exr";
    ExrWriteReport report = writeSpectralExr(file, cube, {});
    EXPECT_EQ(report.clampedToHalfMax, 0u);
    EXPECT_EQ(report.nonFinite, 0u);
    expectBitExact(cube, readSpectralExr(file));
    EXPECT_TRUE(othersThan(file).empty());
}

TEST_F(SpectralExr, HalfStepGridWith881BandsRoundTrips) {
    SpectralCube cube = randomCube(1, 2, Grid{300, 740, 0.5}, 2);
    ASSERT_EQ(cube.bands(), 881);
    fs::path file = dir / "fine.exr";
    writeSpectralExr(file, cube, {});
    expectBitExact(cube, readSpectralExr(file));
}

TEST_F(SpectralExr, EveryCompressionRoundTripsLosslessly) {
    SpectralCube cube = randomCube(9, 4, Grid{400, 700, 10}, 3);
    for (const char* c : {"none", "rle", "zips", "zip", "piz"}) {
        fs::path file = dir / fmt::format("{}.exr", c);
        writeSpectralExr(file, cube, {.compression = c});
        expectBitExact(cube, readSpectralExr(file));
        auto in = OIIO::ImageInput::open(file.string());
        ASSERT_TRUE(in);
        EXPECT_EQ(in->spec().get_string_attribute("compression"), c);
    }
}

TEST_F(SpectralExr, HalfRoundTripWithinHalfPrecision) {
    SpectralCube cube = randomCube(6, 3, Grid{380, 780, 20}, 4, 0.0f, 1000.0f);
    fs::path file = dir / "half.exr";
    ExrWriteReport report = writeSpectralExr(file, cube, {.half = true});
    EXPECT_EQ(report.clampedToHalfMax, 0u);
    SpectralCube back = readSpectralExr(file);
    ASSERT_EQ(back.grid, cube.grid);
    for (size_t i = 0; i < cube.data.size(); ++i)
        EXPECT_NEAR(back.data[i], cube.data[i], std::fabs(cube.data[i]) * (1.0f / 2048) + 1e-7f) << i;
    auto in = OIIO::ImageInput::open(file.string());
    EXPECT_EQ(in->spec().format, OIIO::TypeDesc::HALF);
}

TEST_F(SpectralExr, HalfClampsAndCountsValuesBeyondHalfMax) {
    SpectralCube cube(4, 1, Grid{500, 510, 5});
    cube.data = {1.0f, 7e4f, -1e9f, 65504.0f, 65505.0f, NAN, INFINITY, 2.0f,
                 3.0f, 4.0f, 5.0f, 6.0f};
    fs::path file = dir / "clamp.exr";
    ExrWriteReport report = writeSpectralExr(file, cube, {.half = true});
    EXPECT_EQ(report.clampedToHalfMax, 3u);  // 7e4, -1e9, 65505; 65504 itself is representable
    EXPECT_EQ(report.nonFinite, 2u);
    SpectralCube back = readSpectralExr(file);
    EXPECT_EQ(back.data[1], 65504.0f);
    EXPECT_EQ(back.data[2], -65504.0f);
    EXPECT_EQ(back.data[3], 65504.0f);
    EXPECT_EQ(back.data[4], 65504.0f);
    EXPECT_TRUE(std::isnan(back.data[5]));
    EXPECT_TRUE(std::isinf(back.data[6]));
    // float32 leaves them alone but still counts non-finite values.
    ExrWriteReport full = writeSpectralExr(dir / "full.exr", cube, {});
    EXPECT_EQ(full.clampedToHalfMax, 0u);
    EXPECT_EQ(full.nonFinite, 2u);
    EXPECT_EQ(readSpectralExr(dir / "full.exr").data[2], -1e9f);
}

TEST_F(SpectralExr, GridCrossing1000nmReadsBackInWavelengthOrder) {
    SpectralCube cube(2, 1, Grid{900, 1100, 50});
    for (int x = 0; x < 2; ++x)
        for (int b = 0; b < cube.bands(); ++b) cube.at(x, 0, b) = static_cast<float>(b + 10 * x);
    fs::path file = dir / "ir.exr";
    writeSpectralExr(file, cube, {});
    auto in = OIIO::ImageInput::open(file.string());
    ASSERT_TRUE(in);
    // Stored alphabetically, so the file really is out of wavelength order.
    EXPECT_EQ(in->spec().channelnames.front(), "S0.1000,000000nm");
    in.reset();
    expectBitExact(cube, readSpectralExr(file));
}

TEST_F(SpectralExr, HeaderCarriesLayoutAndMetamerAttributes) {
    SpectralCube cube = randomCube(2, 2, Grid{300, 740, 5}, 5);
    fs::path file = dir / "attrs.exr";
    writeSpectralExr(file, cube, {.extraAttributes = {{"metamer:scene", "cornell.json"}}});
    auto in = OIIO::ImageInput::open(file.string());
    ASSERT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    EXPECT_EQ(spec.get_string_attribute("spectralLayoutVersion"), "1.0");
    EXPECT_EQ(spec.get_string_attribute("emissiveUnits"), "W.m^-2.sr^-1");
    EXPECT_EQ(spec.get_string_attribute("metamer:grid"), "300:740:5");
    EXPECT_EQ(spec.get_string_attribute("metamer:quantity"),
              "spectral radiance per band (docs/physics.md), W·sr⁻¹·m⁻²·nm⁻¹");
    EXPECT_EQ(spec.get_string_attribute("metamer:scene"), "cornell.json");
    EXPECT_EQ(spec.get_string_attribute("compression"), "piz");
    EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
    std::vector<std::string> names(spec.channelnames.begin(), spec.channelnames.end());
    EXPECT_NE(std::find(names.begin(), names.end(), "S0.300,000000nm"), names.end());
    EXPECT_NE(std::find(names.begin(), names.end(), "S0.740,000000nm"), names.end());
    EXPECT_EQ(names.size(), 89u);
}

// The display preview beside the bands: ordinary readers see R, G, B, A first (OpenImageIO orders
// them so), with the display's chromaticities; the spectral reader still sees the bands only.
TEST_F(SpectralExr, PreviewChannelsSitBesideTheBandsAndReadersSeeThemFirst) {
    const SpectralCube cube = randomCube(3, 2, Grid{400, 700, 50}, 9);
    const ExrChromaticities crtLike{{0.62, 0.34}, {0.28, 0.60}, {0.15, 0.06}, {0.31, 0.33}};
    std::vector<float> preview(3 * 2 * 4);
    for (size_t i = 0; i < preview.size(); ++i) preview[i] = i % 4 == 3 ? 1.0f : 0.01f * float(i);
    const fs::path file = dir / "preview.exr";
    for (bool half : {false, true}) {
        SCOPED_TRACE(half);
        {
            SpectralExrWriter w(file, 3, 2, cube.grid, {.half = half, .preview = crtLike});
            // Without its preview a strip is refused, naming the file.
            std::string message;
            try {
                w.writeRows(0, 1, cube.data.data());
            } catch (const Error& e) {
                message = e.what();
            }
            EXPECT_NE(message.find("preview.exr"), std::string::npos) << message;
            EXPECT_NE(message.find("preview"), std::string::npos) << message;
            w.writeRows(0, 1, cube.data.data(), preview.data());
            w.writeRows(1, 1, cube.data.data() + 3 * 7, preview.data() + 3 * 4);
            w.commit();
        }
        auto in = OIIO::ImageInput::open(file.string());
        ASSERT_TRUE(in);
        const OIIO::ImageSpec& spec = in->spec();
        ASSERT_EQ(spec.nchannels, 7 + 4);
        EXPECT_EQ(spec.channelnames[0], "R");
        EXPECT_EQ(spec.channelnames[1], "G");
        EXPECT_EQ(spec.channelnames[2], "B");
        EXPECT_EQ(spec.channelnames[3], "A");
        EXPECT_EQ(spec.alpha_channel, 3);
        const OIIO::ParamValue* c = spec.find_attribute("chromaticities");
        ASSERT_TRUE(c);
        const float* xy = static_cast<const float*>(c->data());
        EXPECT_FLOAT_EQ(xy[0], 0.62f);
        EXPECT_FLOAT_EQ(xy[7], 0.33f);
        std::vector<float> rgba(3 * 2 * 4);
        ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, rgba.data()));
        for (size_t i = 0; i < rgba.size(); ++i) EXPECT_NEAR(rgba[i], preview[i], half ? 1e-3 * preview[i] : 0.0) << i;
        in->close();
        const SpectralCube back = readSpectralExr(file);
        EXPECT_EQ(back.bands(), 7);
        if (!half) expectBitExact(cube, back);
        const std::optional<ExrChromaticities> read = readExrHeader(file, Where{file.string()}).chromaticities;
        ASSERT_TRUE(read);
        EXPECT_NEAR(read->red[0], crtLike.red[0], 1e-7);  // the attribute is float32
        EXPECT_NEAR(read->white[1], crtLike.white[1], 1e-7);
    }
}

TEST_F(SpectralExr, ReadsForeignLayoutsAndIgnoresRgb) {
    // Dot decimals, micrometres, no metamer:grid, RGB channels beside the spectral ones.
    OIIO::ImageSpec spec(2, 1, 6, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "S0.0.5um", "S0.600.0nm", "S0.550nm"};
    std::vector<float> px = {9, 9, 9, 1, 3, 2, 9, 9, 9, 4, 6, 5};
    fs::path file = dir / "foreign.exr";
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out->open(file.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    out->close();
    SpectralCube cube = readSpectralExr(file);
    EXPECT_EQ(cube.grid, (Grid{500, 600, 50}));
    EXPECT_EQ(cube.data, (std::vector<float>{1, 2, 3, 4, 5, 6}));
}

TEST_F(SpectralExr, ReflectiveChannelsAreFlagged) {
    OIIO::ImageSpec spec(1, 1, 3, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"T.400,000000nm", "T.410,000000nm", "T.420,000000nm"};
    std::vector<float> px = {0.1f, 0.2f, 0.3f};
    fs::path file = dir / "refl.exr";
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out->open(file.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    out->close();
    SpectralExrImage image = readSpectralExrImage(file);
    EXPECT_EQ(image.component, SpectralComponent::Reflective);
    EXPECT_EQ(image.cube.grid, (Grid{400, 420, 10}));
    EXPECT_EQ(image.cube.data, px);
    EXPECT_THROW(readSpectralExr(file), Error);
}

TEST_F(SpectralExr, NonUniformGridIsAnErrorNamingTheWavelengths) {
    OIIO::ImageSpec spec(1, 1, 3, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"S0.400,000000nm", "S0.410,000000nm", "S0.430,000000nm"};
    std::vector<float> px = {1, 2, 3};
    fs::path file = dir / "gappy.exr";
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out->open(file.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    out->close();
    try {
        readSpectralExr(file);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_EQ(e.where().file, file.string());
        EXPECT_NE(e.message().find("400 nm and 410 nm"), std::string::npos) << e.message();
    }
}

TEST_F(SpectralExr, ReadErrorsNameTheFile) {
    auto expectInputError = [](const fs::path& p, const std::string& fragment) {
        try {
            readSpectralExr(p);
            ADD_FAILURE() << "expected an error for " << p;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadInput);
            EXPECT_EQ(e.where().file, p.string());
            EXPECT_NE(e.message().find(fragment), std::string::npos) << e.message();
        }
    };
    expectInputError(dir / "missing.exr", "not found");
    std::ofstream(dir / "text.exr") << "hello, not an image\n";
    expectInputError(dir / "text.exr", "OpenEXR");
    // A valid EXR without spectral channels.
    OIIO::ImageSpec spec(1, 1, 3, OIIO::TypeDesc::FLOAT);
    std::vector<float> px = {1, 2, 3};
    auto out = OIIO::ImageOutput::create((dir / "rgb.exr").string());
    ASSERT_TRUE(out->open((dir / "rgb.exr").string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    out->close();
    expectInputError(dir / "rgb.exr", "no spectral channels");
}

TEST_F(SpectralExr, InterruptedWriteLeavesExistingFileUntouched) {
    fs::path file = dir / "keep.exr";
    writeSpectralExr(file, randomCube(3, 3, Grid{400, 700, 10}, 6), {});
    std::string before = slurp(file);
    {
        AtomicOutput out(file);
        EXPECT_EQ(out.tempPath().parent_path(), dir);
        EXPECT_EQ(out.tempPath().extension(), ".exr");
        EXPECT_EQ(out.tempPath().filename().string().rfind(".keep.exr.tmp-", 0), 0u);
        std::ofstream(out.tempPath()) << "half-written";
        EXPECT_EQ(liveTempFileCount(), 1);
        // destroyed without commit(), as when the writer throws
    }
    EXPECT_EQ(liveTempFileCount(), 0);
    EXPECT_EQ(slurp(file), before);
    EXPECT_TRUE(othersThan(file).empty());
}

TEST_F(SpectralExr, FailedWriteLeavesExistingFileUntouched) {
    fs::path file = dir / "keep.exr";
    writeSpectralExr(file, randomCube(3, 3, Grid{400, 700, 10}, 7), {});
    std::string before = slurp(file);
    SpectralCube bad(3, 3, Grid{400, 700, 10});
    bad.data.resize(5);  // inconsistent cube
    EXPECT_THROW(writeSpectralExr(file, bad, {}), Error);
    EXPECT_THROW(writeSpectralExr(file, randomCube(3, 3, Grid{400, 700, 10}, 8), {.compression = "lzma"}),
                 Error);
    EXPECT_EQ(slurp(file), before);
    EXPECT_TRUE(othersThan(file).empty());
}

TEST_F(SpectralExr, SignalCleanupRemovesLiveTempFiles) {
    AtomicOutput a(dir / "a.exr");
    AtomicOutput b(dir / "sub" / "b.exr");  // creates the missing folder
    EXPECT_TRUE(fs::is_directory(dir / "sub"));
    std::ofstream(a.tempPath()) << "x";
    std::ofstream(b.tempPath()) << "y";
    EXPECT_NE(a.tempPath(), b.tempPath());
    removeLiveTempFiles();
    EXPECT_FALSE(fs::exists(a.tempPath()));
    EXPECT_FALSE(fs::exists(b.tempPath()));
}

TEST_F(SpectralExr, CommitReplacesAtomically) {
    fs::path file = dir / "out" / "new.exr";
    SpectralCube cube = randomCube(2, 2, Grid{400, 700, 10}, 9);
    writeSpectralExr(file, cube, {});  // folder created on the way
    SpectralCube second = randomCube(2, 2, Grid{400, 700, 10}, 10);
    writeSpectralExr(file, second, {});
    expectBitExact(second, readSpectralExr(file));
    EXPECT_EQ(std::distance(fs::directory_iterator(dir / "out"), fs::directory_iterator()), 1);
}

// Timing of the default-compression decision: run with --gtest_also_run_disabled_tests.
// Two kinds of content: smooth spectra (a clean render) and the same with 1% noise (Monte Carlo).
TEST_F(SpectralExr, DISABLED_WriteSpeed1024x1024x89) {
    SpectralCube cube(1024, 1024, Grid{300, 740, 5});
    writeSpectralExr(dir / "warm.exr", randomCube(2, 2, Grid{400, 700, 10}, 1), {});  // starts the thread pool
    std::printf("OpenEXR threads: %d (hardware %u)\n", Imf::globalThreadCount(), std::thread::hardware_concurrency());
    for (float noiseLevel : {0.0f, 0.01f}) {
        std::mt19937 rng(11);
        std::normal_distribution<float> noise(0.0f, 1.0f);
        for (int y = 0; y < cube.height; ++y)
            for (int x = 0; x < cube.width; ++x)
                for (int b = 0; b < cube.bands(); ++b)
                    cube.at(x, y, b) = 0.5f + 0.4f * std::sin(0.05f * b + 0.01f * x) * std::cos(0.007f * y) +
                                       noiseLevel * noise(rng);
        for (bool half : {false, true}) {
            for (const char* c : {"none", "zip", "zip:1", "zips", "piz"}) {
                fs::path file = dir / "speed.exr";
                auto t0 = std::chrono::steady_clock::now();
                writeSpectralExr(file, cube, {.half = half, .compression = c});
                auto t1 = std::chrono::steady_clock::now();
                SpectralCube back = readSpectralExr(file);
                auto t2 = std::chrono::steady_clock::now();
                using ms = std::chrono::duration<double, std::milli>;
                std::printf("noise %.2f %-5s %-5s write %7.0f ms  read %7.0f ms  %6.1f MiB\n", noiseLevel,
                            half ? "half" : "float", c, ms(t1 - t0).count(), ms(t2 - t1).count(),
                            fs::file_size(file) / 1048576.0);
                fs::remove(file);
            }
        }
    }
}

// --- Bispectral images: Donaldson matrices ------------------------------------------------------

namespace {

void writeExr(const fs::path& file, int w, int h, const std::vector<std::string>& names, const std::vector<float>& px) {
    OIIO::ImageSpec spec(w, h, int(names.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out->open(file.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    out->close();
}

}  // namespace

TEST_F(SpectralExr, ReadsBispectralChannelsAsADonaldsonMatrix) {
    // Comma and dot decimals, extra dots, micrometres; a pair with no channel is 0; reflective and
    // RGB channels are counted, not read into D.
    fs::path file = dir / "donaldson.exr";
    writeExr(file, 1, 1,
             {"R", "T.400nm.500nm", "T.400nm.0.51um", "T..410,5nm..500nm", "T.400,000000nm", "S0.500nm"},
             {9, 0.25f, 0.5f, 0.125f, 0.9f, 7});
    BispectralExr r = readBispectralExr(file);
    EXPECT_EQ(r.reflectiveChannels, 1u);
    EXPECT_EQ(r.otherChannels, 2u);
    const BispectralMatrix& d = r.matrix;
    EXPECT_EQ(d.in_nm, (std::vector<double>{400, 410.5}));
    ASSERT_EQ(d.out_nm.size(), 2u);
    EXPECT_DOUBLE_EQ(d.out_nm[0], 500);
    EXPECT_NEAR(d.out_nm[1], 510, 1e-9);
    EXPECT_EQ(d.values, (std::vector<double>{0.25, 0.5, 0.125, 0.0}));
    EXPECT_NO_THROW(d.validate(Where{file.string()}));
}

TEST_F(SpectralExr, BispectralErrorsNameTheFileAndChannel) {
    auto expectError = [&](const std::string& name, int w, const std::vector<std::string>& channels,
                           const std::vector<float>& px, const std::string& what) {
        fs::path file = dir / name;
        writeExr(file, w, 1, channels, px);
        try {
            readBispectralExr(file);
            ADD_FAILURE() << name << " was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadInput) << e.what();
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    const std::vector<std::string> four = {"T.400nm.500nm", "T.400nm.510nm", "T.410nm.500nm", "T.410nm.510nm"};
    expectError("texture.exr", 2, four, std::vector<float>(8, 0.1f), "is a 2×1 image; a Donaldson matrix file must be 1×1");
    expectError("nan.exr", 1, four, {0.1f, NAN, 0.1f, 0.1f}, "channel 'T.400nm.510nm': nan is not a finite number");
    expectError("negative.exr", 1, four, {0.1f, 0.1f, -2.0f, 0.1f}, "channel 'T.410nm.500nm': -2 is negative");
    expectError("duplicate.exr", 1, {"T.400nm.500nm", "T.400,0nm.500nm", "T.410nm.510nm"}, {0.1f, 0.2f, 0.3f},
                "both hold D(400 nm, 500 nm)");
    expectError("reflective.exr", 1, {"T.400nm", "T.410nm"}, {0.5f, 0.6f},
                "no bispectral channels (expected T.<λin>nm.<λout>nm; found T.400nm, T.410nm)");
    expectError("one-row.exr", 1, {"T.400nm.500nm", "T.400nm.510nm"}, {0.1f, 0.2f},
                "name 1 excitation and 2 emission wavelength(s)");
    fs::path png = dir / "image.exr";
    {
        std::ofstream(png, std::ios::binary) << "not an image at all";
    }
    try {
        readBispectralExr(png);
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(std::string(e.what()).find("image.exr"), std::string::npos) << e.what();
    }
}
