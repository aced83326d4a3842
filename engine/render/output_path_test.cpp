#include "render/output_path.h"

#include "core/error.h"

#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>

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
    fs::create_directories(d / "scan.tiff");
    EXPECT_EQ(parseOutputPath((d / "scan.tiff").string(), "--out").folder, d / "scan.tiff");  // even a refused name
    const OutputPath slash = parseOutputPath((d / "new.exr/").string(), "--out");    // a trailing '/'
    EXPECT_EQ(slash.extension, "");
    EXPECT_EQ(slash.stem, "");
    EXPECT_EQ(parseOutputPath((d / "new.tiff/").string(), "--out").extension, "");
    EXPECT_EQ(parseOutputPath((d / "out").string(), "--out").extension, "");  // no extension
}

// Issue 46: a dot in a folder's name no longer makes it ambiguous.
TEST(OutputPath, ANameWithADotThatNamesNoFileIsAFolder) {
    for (const std::string name : {"runs/v1.2", "2026.12.05", "out.d", "renders/take.3", "notes.txt", "x.exr.d"}) {
        const OutputPath p = parseOutputPath(name, "--out");
        EXPECT_EQ(p.folder, fs::path(name)) << name;
        EXPECT_EQ(p.stem, "") << name;
        EXPECT_EQ(p.extension, "") << name;
    }
    // An existing file of such a name is still not a folder.
    const fs::path d = freshDir("dotted");
    std::ofstream(d / "v1.2") << "x";
    EXPECT_NE(inputError((d / "v1.2").string()).find("is a file, not a folder"), std::string::npos);
}

TEST(OutputPath, AnImageOrCubeMetamerDoesNotWriteIsAnErrorNamingTheFlag) {
    const std::string tiff = inputError("result.tiff");
    EXPECT_NE(tiff.find("--out: 'result.tiff' names a .tiff file, which Metamer does not write"), std::string::npos)
        << tiff;
    EXPECT_NE(tiff.find("Metamer writes NAME.exr, NAME.h5, NAME.mat, NAME.hdr or NAME.png"), std::string::npos) << tiff;
    EXPECT_NE(tiff.find("'result.tiff/'"), std::string::npos) << tiff;
    // In any case, and every listed one.
    EXPECT_NE(inputError("shots/A.JPG").find("'shots/A.JPG' names a .JPG file"), std::string::npos);
    const std::vector<std::string> refusedList = refusedOutputExtensions();
    EXPECT_GE(refusedList.size(), 20u);
    for (const std::string& ext : refusedList) {
        std::string upper = ext;
        for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        EXPECT_NE(inputError("x" + ext).find("'x" + ext + "' names a " + ext + " file"), std::string::npos) << ext;
        EXPECT_NE(inputError("x" + upper).find("'x" + upper + "' names a " + upper + " file"), std::string::npos)
            << upper;
        EXPECT_EQ(namedCubeFormat(ext), nullptr) << ext;  // never an output's own
    }
    // Where Metamer writes the same thing under another name, the error says which.
    const std::string hdf5 = inputError("cube.hdf5");
    EXPECT_NE(hdf5.find("'cube.hdf5' names a .hdf5 file: HDF5 cubes are NAME.h5; Metamer writes NAME.exr"),
              std::string::npos) << hdf5;
    EXPECT_NE(inputError("cube.he5").find("HDF5 cubes are NAME.h5"), std::string::npos);
    EXPECT_NE(inputError("cube.img").find("an ENVI cube is named by its header, NAME.hdr"), std::string::npos);
    EXPECT_NE(inputError("cube.bil").find("--format envi:bil"), std::string::npos);
    EXPECT_NE(inputError("shot.dng").find("--sensor writes a DNG beside the cube"), std::string::npos);
}

TEST(OutputPath, AnOutputsExtensionInAnotherCaseIsAnError) {
    const std::string upper = inputError("renders/X.EXR");
    EXPECT_NE(upper.find("--out: 'renders/X.EXR': output files are named in lower case; write 'renders/X.exr'"),
              std::string::npos) << upper;
    EXPECT_NE(upper.find("'renders/X.EXR/'"), std::string::npos) << upper;
    EXPECT_NE(inputError("x.Png").find("write 'x.png'"), std::string::npos);
    EXPECT_NE(inputError("x.H5").find("write 'x.h5'"), std::string::npos);
}

TEST(OutputPath, ExistingFilesAndDevicesAreNotFolders) {
    const fs::path d = freshDir("file");
    std::ofstream(d / "plain") << "x";
    EXPECT_NE(inputError((d / "plain").string()).find("is a file, not a folder"), std::string::npos);
    EXPECT_NE(inputError((d / "plain/").string()).find("is a file, not a folder"), std::string::npos);
    EXPECT_NE(inputError("/dev/null").find("not a folder"), std::string::npos);
    EXPECT_NE(inputError("").find("got an empty string"), std::string::npos);
}

// docs/cli.md lists what -o refuses; the table in output_path.cpp is the one place it is decided.
TEST(OutputPath, TheDocsListTheRefusedExtensions) {
    std::ifstream in(std::string(METAMER_SOURCE_DIR) + "/docs/cli.md");
    const std::string docs((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t from = docs.find("- **Refused**");
    ASSERT_NE(from, std::string::npos) << "docs/cli.md, \"Output names\", has no refused list";
    const std::string section = docs.substr(from, docs.find("\n- ", from + 1) - from);
    for (const std::string& ext : refusedOutputExtensions())
        EXPECT_NE(section.find("`" + ext + "`"), std::string::npos) << ext << " is refused but not in docs/cli.md";
    // And nothing listed there that is not refused: every `.ext` counted (not "`X`." closing a sentence).
    size_t n = 0;
    for (size_t at = section.find("`."); at != std::string::npos; at = section.find("`.", at + 1))
        n += std::isalnum(static_cast<unsigned char>(section[at + 2])) ? 1 : 0;
    EXPECT_EQ(n, refusedOutputExtensions().size()) << section;
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
