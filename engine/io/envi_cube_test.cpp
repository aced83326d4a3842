#include "io/envi_cube.h"

#include "io/atomic_file.h"

#include "support/cubes.h"
#include "support/temp_folder.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>
#include <sys/stat.h>
#include <unistd.h>

using namespace metamer;
namespace fs = std::filesystem;
using test::expectBitExact;
using test::randomCube;
using test::patternCube;
using test::expectInputError;
using test::slurp;
using test::writeText;

namespace {

class EnviCube : public test::TempFolderTest {};

template <typename T>
std::string rawBytes(const std::vector<T>& values, bool swap = false) {
    std::string bytes(values.size() * sizeof(T), '\0');
    std::memcpy(bytes.data(), values.data(), bytes.size());
    if (swap)
        for (size_t i = 0; i < bytes.size(); i += sizeof(T)) std::reverse(bytes.begin() + i, bytes.begin() + i + sizeof(T));
    return bytes;
}

void writeInStrips(const fs::path& header, const SpectralCube& cube, const std::vector<int>& strips,
                   const EnviWriteOptions& options) {
    EnviCubeWriter writer(header, cube.width, cube.height, cube.grid, options);
    int row = 0;
    for (int rows : strips) {
        writer.writeRows(row, rows, cube.pixel(0, row));
        row += rows;
    }
    ASSERT_EQ(row, cube.height);
    writer.commit();
}

// A header for a 2×1×3 float32 cube, with `extra` lines and without the keys in `drop`.
std::string header(const std::string& extra = "", const std::vector<std::string>& drop = {}) {
    const std::vector<std::pair<std::string, std::string>> keys = {
        {"samples", "2"},          {"lines", "1"},           {"bands", "3"},
        {"header offset", "0"},    {"data type", "4"},       {"interleave", "bsq"},
        {"byte order", "0"},       {"wavelength units", "Nanometers"},
        {"wavelength", "{400, 410, 420}"}};
    std::string text = "ENVI\n";
    for (const auto& [k, v] : keys)
        if (std::find(drop.begin(), drop.end(), k) == drop.end()) text += k + " = " + v + "\n";
    return text + extra;
}

const Where kWhere{"test.hdr"};

}  // namespace

TEST_F(EnviCube, RoundTripOfEveryInterleaveInUnevenStripsIsBitExact) {
    const SpectralCube cube = randomCube(7, 5, Grid{400, 520, 10}, 1);
    ASSERT_EQ(cube.bands(), 13);
    for (EnviInterleave interleave : {EnviInterleave::Bsq, EnviInterleave::Bil, EnviInterleave::Bip}) {
        for (SpectralComponent component : {SpectralComponent::Emissive, SpectralComponent::Reflective}) {
            SCOPED_TRACE(fmt::format("{} {}", enviInterleaveName(interleave), int(component)));
            const fs::path file = dir / "cube.hdr";
            writeInStrips(file, cube, {2, 1, 2}, {.interleave = interleave, .component = component});
            EXPECT_EQ(namesIn(), (std::vector<std::string>{"cube.hdr", "cube.img"}));
            EXPECT_EQ(fs::file_size(dir / "cube.img"), 7u * 5 * 13 * 4);
            const SpectralImage back = readEnviCube(file);
            EXPECT_EQ(back.component, component);
            expectBitExact(cube, back.cube);
            expectBitExact(cube, readEnviCube(dir / "cube.img").cube);  // from the data file too
        }
    }
}

TEST_F(EnviCube, DataFileIsInTheInterleaveItsHeaderNames) {
    const SpectralCube cube = patternCube(3, 2, Grid{500, 530, 10});
    const size_t S = 3, L = 2, B = 4;
    for (EnviInterleave interleave : {EnviInterleave::Bsq, EnviInterleave::Bil, EnviInterleave::Bip}) {
        const fs::path file = dir / fmt::format("{}.hdr", enviInterleaveName(interleave));
        writeInStrips(file, cube, {1, 1}, {.interleave = interleave});
        const std::string bytes = slurp(enviDataPathFor(file));
        ASSERT_EQ(bytes.size(), S * L * B * 4);
        for (size_t y = 0; y < L; ++y)
            for (size_t x = 0; x < S; ++x)
                for (size_t b = 0; b < B; ++b) {
                    const size_t i = interleave == EnviInterleave::Bsq   ? (b * L + y) * S + x
                                     : interleave == EnviInterleave::Bil ? (y * B + b) * S + x
                                                                         : (y * S + x) * B + b;
                    float v;
                    std::memcpy(&v, bytes.data() + i * 4, 4);
                    EXPECT_EQ(v, cube.at(int(x), int(y), int(b))) << enviInterleaveName(interleave) << x << y << b;
                }
        EXPECT_EQ(parseEnviHeader(slurp(file), kWhere).interleave, interleave);
    }
}

TEST_F(EnviCube, HeaderCarriesEveryKey) {
    const SpectralCube cube = randomCube(4, 3, Grid{400, 700, 2.5}, 2);
    const fs::path file = dir / "keys.hdr";
    writeEnviCube(file, cube,
                  {.interleave = EnviInterleave::Bil,
                   .attributes = {{"metamer:scene", "line one\nline {two}"}, {"spp", "64"}}});
    const std::string text = slurp(file);
    EXPECT_EQ(text.rfind("ENVI\n", 0), 0u);
    const EnviHeader h = parseEnviHeader(text, kWhere);
    EXPECT_EQ(h.samples, 4);
    EXPECT_EQ(h.lines, 3);
    EXPECT_EQ(h.bands, 121);
    EXPECT_EQ(h.headerOffset, 0u);
    EXPECT_EQ(h.dataType, 4);
    EXPECT_EQ(h.byteOrder, std::endian::native == std::endian::little ? 0 : 1);
    EXPECT_EQ(h.wavelengthUnits, "Nanometers");
    ASSERT_EQ(h.wavelengths_nm.size(), 121u);
    ASSERT_EQ(h.fwhm_nm.size(), 121u);
    for (int b = 0; b < 121; ++b) {
        EXPECT_EQ(h.wavelengths_nm[size_t(b)], cube.grid.wavelength(b));
        EXPECT_EQ(h.fwhm_nm[size_t(b)], 2.5);
    }
    EXPECT_EQ(h.field("file type"), "ENVI Standard");
    const std::string names = h.field("band names").value_or("");
    EXPECT_EQ(names.rfind("400 nm, 402.5 nm, 405 nm,", 0), 0u) << names;
    // 610, 550 and 465 nm are bands 84, 60 and 26 of 400:700:2.5; the header counts from 1.
    EXPECT_EQ(h.field("default bands"), "85, 61, 27");
    EXPECT_EQ(h.field("metamer quantity"), "spectral radiance");
    EXPECT_EQ(h.field("metamer units"), "W.sr^-1.m^-2.nm^-1");
    EXPECT_EQ(h.field("metamer grid"), "400:700:2.5");
    EXPECT_EQ(h.field("metamer resampling"), "interpolate");
    EXPECT_EQ(h.field("metamer scene"), "line one line (two)");
    EXPECT_EQ(h.field("metamer spp"), "64");
    EXPECT_NE(h.field("description").value_or("").find("W.sr^-1.m^-2.nm^-1"), std::string::npos);
}

TEST_F(EnviCube, DefaultBandsAreClampedIntoTheGrid) {
    writeEnviCube(dir / "nir.hdr", randomCube(1, 1, Grid{700, 900, 50}, 3));
    EXPECT_EQ(parseEnviHeader(slurp(dir / "nir.hdr"), kWhere).field("default bands"), "1, 1, 1");
    writeEnviCube(dir / "uv.hdr", randomCube(1, 1, Grid{300, 400, 50}, 3));
    EXPECT_EQ(parseEnviHeader(slurp(dir / "uv.hdr"), kWhere).field("default bands"), "3, 3, 3");
}

TEST_F(EnviCube, EqualsTheExrWritersValues) {
    const SpectralCube cube = randomCube(9, 6, Grid{300, 740, 5}, 4);
    writeSpectralExr(dir / "cube.exr", cube, {.compression = "zip"});
    writeEnviCube(dir / "cube.hdr", cube, {.interleave = EnviInterleave::Bil});
    expectBitExact(readSpectralExr(dir / "cube.exr"), readEnviCube(dir / "cube.hdr").cube);
}

TEST_F(EnviCube, AbandonedWriterLeavesNeitherFile) {
    const SpectralCube cube = randomCube(4, 3, Grid{400, 500, 50}, 5);
    const int liveBefore = liveTempFileCount();
    for (EnviInterleave interleave : {EnviInterleave::Bsq, EnviInterleave::Bil, EnviInterleave::Bip}) {
        EnviCubeWriter writer(dir / "abandoned.hdr", 4, 3, cube.grid, {.interleave = interleave});
        writer.writeRows(0, 2, cube.data.data());
        EXPECT_EQ(liveTempFileCount(), liveBefore + 2);
    }
    EXPECT_TRUE(namesIn().empty()) << ::testing::PrintToString(namesIn());
    EXPECT_EQ(liveTempFileCount(), liveBefore);
}

TEST_F(EnviCube, WriterMisuseIsAnError) {
    const Grid grid{400, 500, 50};
    const std::vector<float> rows(4 * 3 * 3, 1.0f);
    EXPECT_THROW(EnviCubeWriter(dir / "cube.img", 4, 3, grid), Error);  // the header's name is .hdr
    EnviCubeWriter writer(dir / "misuse.hdr", 4, 3, grid);
    EXPECT_THROW(writer.writeRows(1, 1, rows.data()), Error);
    writer.writeRows(0, 2, rows.data());
    EXPECT_THROW(writer.writeRows(2, 2, rows.data()), Error);  // past the last row
    EXPECT_THROW(writer.commit(), Error);
}

TEST_F(EnviCube, SiblingsAreFoundFromEitherFile) {
    const SpectralCube cube = randomCube(2, 2, Grid{400, 420, 10}, 6);
    writeEnviCube(dir / "a.hdr", cube);
    // <stem>.img.hdr beside <stem>.img, as GDAL may write it.
    fs::rename(dir / "a.hdr", dir / "a.img.hdr");
    expectBitExact(cube, readEnviCube(dir / "a.img").cube);
    expectBitExact(cube, readEnviCube(dir / "a.img.hdr").cube);
    // A .dat data file.
    fs::rename(dir / "a.img.hdr", dir / "b.hdr");
    fs::rename(dir / "a.img", dir / "b.dat");
    expectBitExact(cube, readEnviCube(dir / "b.hdr").cube);
    expectBitExact(cube, readEnviCube(dir / "b.dat").cube);
    fs::remove(dir / "b.dat");
    expectInputError([&] { readEnviCube(dir / "b.hdr"); }, (dir / "b.hdr").string(), "", "no ENVI data file");
    writeText(dir / "lonely.img", std::string(24, '\0'));
    expectInputError([&] { readEnviCube(dir / "lonely.img"); }, (dir / "lonely.img").string(), "", "no ENVI header");
}

TEST_F(EnviCube, ByteOrder1AndFloat64AndHeaderOffsetRead) {
    const std::vector<float> bsq = {1.5f, -2.0f, 3.25f, 4.0f, 1e-3f, 6.0f};  // band-major, 2 samples
    const bool bigHost = std::endian::native == std::endian::big;
    writeText(dir / "swapped.hdr", header("", {"byte order"}) + fmt::format("byte order = {}\n", bigHost ? 0 : 1));
    writeText(dir / "swapped.img", rawBytes(bsq, true));
    SpectralImage image = readEnviCube(dir / "swapped.hdr");
    EXPECT_EQ(image.cube.grid, (Grid{400, 420, 10}));
    EXPECT_EQ(image.cube.data, (std::vector<float>{1.5f, 3.25f, 1e-3f, -2.0f, 4.0f, 6.0f}));

    const std::vector<double> bip = {0.1, 0.2, 0.3, 1e300, -1e300, 0.6};
    writeText(dir / "f64.hdr", header("", {"data type", "interleave", "header offset"}) +
                              "data type = 5\ninterleave = BIP\nheader offset = 16\n");
    writeText(dir / "f64.img", std::string(16, 'x') + rawBytes(bip));
    image = readEnviCube(dir / "f64.hdr");
    EXPECT_EQ(image.cube.data[0], 0.1f);
    EXPECT_EQ(image.cube.data[2], 0.3f);
    EXPECT_EQ(image.cube.data[3], INFINITY);
    EXPECT_EQ(image.cube.data[4], -INFINITY);
    EXPECT_EQ(image.cube.data[5], 0.6f);
}

TEST_F(EnviCube, MicrometresAndForeignSpellingsParse) {
    const EnviHeader h = parseEnviHeader(
        "\n\nENVI\r\n; a comment = not a key\nSamples = 2\nLINES=1\nBands   =  3\nData  Type = 4\n"
        "interleave = bil\nbyte order = 0\nwavelength units = Micrometers\n"
        "wavelength = {\n  0.4,\n  0.41,\n  0.42 }\nfwhm = {0.01, 0.01, 0.01}\nunknown key = {kept, too}\n",
        kWhere);
    EXPECT_EQ(h.samples, 2);
    EXPECT_EQ(h.interleave, EnviInterleave::Bil);
    ASSERT_EQ(h.wavelengths_nm.size(), 3u);
    EXPECT_DOUBLE_EQ(h.wavelengths_nm[0], 400);
    EXPECT_DOUBLE_EQ(h.wavelengths_nm[2], 420);
    EXPECT_DOUBLE_EQ(h.fwhm_nm[1], 10);
    EXPECT_EQ(h.field("unknown key"), "kept, too");
    EXPECT_EQ(parseEnviHeader(header("", {"wavelength units"}) + "wavelength units = um\n", kWhere).wavelengths_nm[0],
              400000.0);
}

TEST_F(EnviCube, MalformedHeadersAreInputErrorsNamingTheKey) {
    auto parse = [](std::string text) { return [text] { parseEnviHeader(text, kWhere); }; };
    EXPECT_NO_THROW(parseEnviHeader(header(), kWhere));
    expectInputError(parse(header("", {"byte order"})), "test.hdr", "byte order", "missing");
    expectInputError(parse(header("", {"samples"})), "test.hdr", "samples", "missing");
    expectInputError(parse(header("", {"interleave"})), "test.hdr", "interleave", "missing");
    expectInputError(parse(header("", {"wavelength"})), "test.hdr", "wavelength", "missing");
    expectInputError(parse(header("", {"wavelength units"})), "test.hdr", "wavelength units", "missing");
    expectInputError(parse(header("", {"data type"}) + "data type = 12\n"), "test.hdr", "data type",
                     "12 (16-bit unsigned integer) is not supported: only 4 (float32) and 5 (float64)");
    expectInputError(parse(header("", {"wavelength"}) + "wavelength = {400, 410}\n"), "test.hdr", "wavelength",
                     "2 values for 3 bands");
    expectInputError(parse(header("fwhm = {1, 2, 3, 4}\n")), "test.hdr", "fwhm", "4 values for 3 bands");
    expectInputError(parse(header("", {"wavelength"}) + "wavelength = {400, nan, 420}\n"), "test.hdr", "wavelength",
                     "value 2 ('nan') is not a finite number");
    expectInputError(parse(header("", {"wavelength units"}) + "wavelength units = Unknown\n"), "test.hdr",
                     "wavelength units", "'Unknown'");
    expectInputError(parse(header("", {"byte order"}) + "byte order = 2\n"), "test.hdr", "byte order", "from 0 to 1");
    expectInputError(parse(header("", {"samples"}) + "samples = 65537\n"), "test.hdr", "samples", "from 1 to 65536");
    expectInputError(parse(header("", {"bands"}) + "bands = 10001\n"), "test.hdr", "bands", "from 1 to 10000");
    expectInputError(parse(header("", {"lines"}) + "lines = 1.5\n"), "test.hdr", "lines", "'1.5'");
    expectInputError(parse(header("", {"interleave"}) + "interleave = bsqq\n"), "test.hdr", "interleave", "'bsqq'");
    expectInputError(parse(header("file type = ENVI Spectral Library\n")), "test.hdr", "file type", "ENVI Standard");
    // Unterminated brace: the line where it opened (header() has 10 lines).
    expectInputError(parse(header("description = {never\nclosed\n")), "test.hdr", "description", "never closed", 11);
    expectInputError(parse(header("band names = {a, b} c\n")), "test.hdr", "band names", "after the closing", 11);
    expectInputError(parse(header("just words\n")), "test.hdr", "", "expected 'key = value'", 11);
    expectInputError(parse(header(" = 3\n")), "test.hdr", "", "has no key", 11);
    expectInputError(parse("ENVY\nsamples = 1\n"), "test.hdr", "", "not an ENVI header", 1);
    expectInputError(parse(""), "test.hdr", "", "empty");
    expectInputError(parse(header() + std::string("x = a\0b\n", 8)), "test.hdr", "", "NUL byte", 11);
    expectInputError(parse(header() + std::string((16 << 20) + 1, ' ')), "test.hdr", "", "over 16 MiB");
}

TEST_F(EnviCube, MalformedCubesAreInputErrorsNamingTheFile) {
    const std::string hdr = (dir / "c.hdr").string(), img = (dir / "c.img").string();
    const std::vector<float> six = {1, 2, 3, 4, 5, 6};
    auto read = [](const std::string& p) { return [p] { readEnviCube(p); }; };

    writeText(hdr, header());
    writeText(img, rawBytes(six).substr(0, 20));
    expectInputError(read(hdr), img, "", "is 20 bytes; the header (c.hdr) describes 24 bytes");
    expectInputError(read(img), img, "", "truncated");
    writeText(img, rawBytes(six) + "!");
    expectInputError(read(hdr), img, "", "too long");

    writeText(img, rawBytes(six));
    writeText(hdr, header("", {"wavelength"}) + "wavelength = {400, 410, 430}\n");
    expectInputError(read(hdr), hdr, "wavelength", "not on a uniform grid");
    writeText(hdr, header("", {"wavelength"}) + "wavelength = {420, 410, 400}\n");
    expectInputError(read(hdr), hdr, "wavelength", "not increasing");
    writeText(hdr, header("metamer quantity = radiance\n"));
    expectInputError(read(hdr), hdr, "metamer quantity", "'radiance'");
    writeText(hdr, header("", {"byte order"}));
    expectInputError(read(img), hdr, "byte order", "missing");

    expectInputError(read((dir / "missing.hdr").string()), (dir / "missing.hdr").string(), "", "not found");
    expectInputError(read(dir.string()), dir.string(), "", "is a folder, not a file");
    expectInputError(read("/dev/zero"), "/dev/zero", "", "not a regular file");
}

TEST_F(EnviCube, DataFilesThatAreNotRegularFilesAreRefusedBeforeOpening) {
    writeText(dir / "fifo.hdr", header());
    ASSERT_EQ(::mkfifo((dir / "fifo.img").c_str(), 0600), 0);
    // Opening a FIFO for reading would block until a writer came: the check must come first.
    expectInputError([&] { readEnviCube(dir / "fifo.hdr"); }, (dir / "fifo.img").string(), "", "not a regular file");
    expectInputError([&] { readEnviCube(dir / "fifo.img"); }, (dir / "fifo.img").string(), "", "not a regular file");
    writeText(dir / "folder.hdr", header());
    fs::create_directory(dir / "folder.img");
    expectInputError([&] { readEnviCube(dir / "folder.hdr"); }, (dir / "folder.img").string(), "",
                     "is a folder, not a file");
}

TEST_F(EnviCube, HeaderParserThrowsNothingButMetamerErrorOnRandomBytes) {
    // Random bytes, and random splices of header-like tokens (which reach deeper into the parser).
    const std::vector<std::string> tokens = {"ENVI\n", "samples = 2\n", "lines = 1\n", "bands = 3\n", "{", "}",
                                             "=", "\n", ",", "data type = 5\n", "byte order = 1\n",
                                             "interleave = bip\n", "wavelength units = nm\n", "wavelength = {",
                                             "400, 410, 420}\n", "1e999", "-0", "nan", ";", "\r", "\xff", "µm"};
    std::mt19937 rng(12345);
    int parsed = 0;
    for (int i = 0; i < 3000; ++i) {
        std::string text;
        if (i % 2 == 0) {
            text.resize(rng() % 200);
            for (char& c : text) c = char(rng() % 256);
        } else {
            text = header();
            for (int k = int(rng() % 6); k > 0; --k) {
                const size_t at = rng() % (text.size() + 1);
                text.insert(at, tokens[rng() % tokens.size()]);
            }
            if (rng() % 3 == 0) text.erase(rng() % text.size(), rng() % 20);
        }
        try {
            const EnviHeader h = parseEnviHeader(text, kWhere);
            ++parsed;
            EXPECT_EQ(h.wavelengths_nm.size(), size_t(h.bands));
            EXPECT_TRUE(h.fwhm_nm.empty() || h.fwhm_nm.size() == size_t(h.bands));
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadInput);
        }
        // Anything else escapes and fails the test.
    }
    EXPECT_GT(parsed, 0);
}
