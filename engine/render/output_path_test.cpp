#include "render/output_path.h"

#include "core/error.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;
using namespace metamer;

namespace {

fs::path freshDir(const std::string& name) {
    fs::path d = fs::temp_directory_path() / ("metamer-output-path-" + name);
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::string inputError(const std::string& text) {
    try {
        parseOutputPath(text, "--out");
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        return e.text();
    }
    return "";
}

}  // namespace

TEST(OutputPath, AFileNameGivesTheStemAndTheFolder) {
    const OutputPath p = parseOutputPath("renders/result.exr", "--out");
    EXPECT_EQ(p.folder, fs::path("renders"));
    EXPECT_EQ(p.stem, "result");
    EXPECT_EQ(p.extension, ".exr");
    const OutputPath here = parseOutputPath("x.h5", "--out");
    EXPECT_EQ(here.folder, fs::path("."));
    EXPECT_EQ(here.extension, ".h5");
    EXPECT_EQ(namedCubeFormat(".h5")->name, "hdf5");
    EXPECT_EQ(namedCubeFormat(".hdr")->name, "envi");
    EXPECT_EQ(namedCubeFormat(".png"), nullptr);
}

TEST(OutputPath, AFolderStaysAFolder) {
    const fs::path d = freshDir("folder");
    fs::create_directories(d / "looks.exr");
    EXPECT_EQ(parseOutputPath((d / "looks.exr").string(), "--out").extension, "");  // exists: a folder
    const OutputPath slash = parseOutputPath((d / "new.exr/").string(), "--out");    // a trailing '/'
    EXPECT_EQ(slash.extension, "");
    EXPECT_EQ(slash.stem, "");
    EXPECT_EQ(parseOutputPath((d / "out").string(), "--out").extension, "");  // no extension
}

TEST(OutputPath, AmbiguousNamesAreErrorsNamingTheFlag) {
    const std::string tiff = inputError("result.tiff");
    EXPECT_NE(tiff.find("--out: 'result.tiff' is ambiguous"), std::string::npos) << tiff;
    EXPECT_NE(tiff.find("NAME.exr, NAME.h5, NAME.hdr or NAME.png"), std::string::npos) << tiff;
    EXPECT_NE(tiff.find("'result.tiff/'"), std::string::npos) << tiff;
    const fs::path d = freshDir("file");
    std::ofstream(d / "plain") << "x";
    EXPECT_NE(inputError((d / "plain").string()).find("is a file, not a folder"), std::string::npos);
    EXPECT_NE(inputError((d / "plain/").string()).find("is a file, not a folder"), std::string::npos);
    EXPECT_NE(inputError("/dev/null").find("not a folder"), std::string::npos);
}

TEST(OutputPath, TheNamedFileMustBeWritten) {
    auto error = [](const std::string& file, bool cube, bool png, const std::vector<std::string>& formats,
                    const std::string& from) -> std::string {
        try {
            requireNamedOutput(file, cube, png, parseCubeFormats(formats, Where{"", "--format"}), from);
        } catch (const Error& e) {
            return e.text();
        }
        return "";
    };
    EXPECT_EQ(error("x.exr", true, true, {"exr"}, ""), "");
    EXPECT_EQ(error("x.png", false, true, {"exr"}, ""), "");
    EXPECT_NE(error("x.png", true, false, {"exr"}, "").find("--out: 'x.png' names the display PNG"), std::string::npos);
    EXPECT_NE(error("x.exr", false, true, {"exr"}, "").find("which this run does not write"), std::string::npos);
    const std::string clash = error("x.h5", true, true, {"exr"}, "--format");
    EXPECT_NE(clash.find("'x.h5' names a cube in hdf5 format, but --format asks for exr; name the file x.exr, or add hdf5 to "
                         "--format"), std::string::npos) << clash;
}
