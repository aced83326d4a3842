// Special files given wherever the program reads a file (issue 19, class 1): a FIFO would block a
// read forever, /dev/zero never ends, a folder is no data. Every reader goes through one check
// (core/file_reads.h, requireRegularFile / readWholeFile), so each case must end at once with exit
// status 2 and one line saying what the file is — under a timeout, so that a reader that opens
// the FIFO fails the test instead of hanging it. FIFOs cannot be committed: they are made here.
#include "support/cli.h"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace metamer;

namespace {

class SpecialFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("metamer-special-files-" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "folder.csv");
        for (const char* name : {"fifo.json", "fifo.csv", "fifo.png", "fifo.gltf", "fifo.exr", "fifo.h5"})
            ASSERT_EQ(::mkfifo((dir_ / name).c_str(), 0600), 0) << name;
        // A valid reference cube for compare's other side.
        write("valid.json", scene(R"("diffuse": 0.5)"));
        test::CliRun r = run("render valid.json --out ref --write cube,png");
        ASSERT_EQ(r.code, 0) << r.output;
    }
    void TearDown() override { fs::remove_all(dir_); }

    static std::string scene(const std::string& material, const std::string& object = "") {
        return R"({"grid": {"start_nm": 400, "end_nm": 700, "step_nm": 10},
  "camera": {"position": [0, 0, 3], "target": [0, 0, 0], "width": 8, "height": 8},
  "lights": [{"type": "directional", "direction": [0, 0, -1], "spectrum": "illuminants/D65", "scale": 0.01}],
  "materials": {"m": {)" + material + R"(}},
  "objects": [)" + (object.empty() ? R"({"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [2, 2], "material": "m"})" : object) + "]}";
    }
    void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
    test::CliRun run(const std::string& args) {
        test::CliOptions o;
        o.dir = dir_.string();
        o.timeoutSeconds = 60;
        o.stderrOnly = true;
        return test::runMetamer(args, o);
    }
    // Exit 2 at once, one line, naming `file` and saying `what`.
    void expectRefused(const std::string& args, const std::string& file, const std::string& what) {
        SCOPED_TRACE(args);
        test::CliRun r = run(args);
        EXPECT_EQ(r.code, 2) << r.output;
        EXPECT_NE(r.output.find(file), std::string::npos) << r.output;
        EXPECT_NE(r.output.find(what), std::string::npos) << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    }

    fs::path dir_;
};

const std::string kFifo = "is not a regular file (a FIFO)";

TEST_F(SpecialFiles, ASceneFileThatIsAFifo) { expectRefused("render fifo.json --out o", "fifo.json", kFifo); }

TEST_F(SpecialFiles, EveryFileASceneNames) {
    write("spectrum.json", scene(R"("diffuse": "fifo.csv")"));
    expectRefused("render spectrum.json --out o", "materials.m.diffuse: spectrum file 'fifo.csv'", kFifo);
    write("folder.json", scene(R"("diffuse": "folder.csv")"));
    expectRefused("render folder.json --out o", "spectrum file 'folder.csv'", "is a folder, not a file");
    write("texture.json", scene(R"("textures": {"diffuse": "fifo.png"})"));
    expectRefused("render texture.json --out o", "texture file 'fifo.png'", kFifo);
    write("cube-texture.json", scene(R"("textures": {"diffuse": "fifo.h5"})"));
    expectRefused("render cube-texture.json --out o", "texture file 'fifo.h5'", kFifo);
    write("mesh.json", scene(R"("diffuse": 0.5)", R"({"mesh": "fifo.gltf", "material": "m"})"));
    expectRefused("render mesh.json --out o", "mesh file 'fifo.gltf'", kFifo);
    write("donaldson.json", scene(R"("diffuse": 0.5, "fluorescence": {"matrix": "fifo.csv"})"));
    expectRefused("render donaldson.json --out o", "Donaldson matrix file 'fifo.csv'", kFifo);
}

TEST_F(SpecialFiles, ADetectorFile) {
    expectRefused("render valid.json --out o --detector csv:fifo.csv", "fifo.csv", kFifo);
}

TEST_F(SpecialFiles, EveryFileCompareReads) {
    expectRefused("compare fifo.exr ref/valid.exr", "fifo.exr", kFifo);
    expectRefused("compare ref/valid.exr fifo.exr", "fifo.exr", kFifo);
    expectRefused("compare ref/valid.exr ref/valid.exr --mask fifo.png", "fifo.png", kFifo);
    expectRefused("compare ref/valid.exr ref/valid.exr --tolerance fifo.json", "fifo.json", kFifo);
    expectRefused("compare ref/valid.exr ref/valid.exr --tolerance /dev/zero", "/dev/zero",
                  "is not a regular file (a character device)");
    expectRefused("compare /dev/zero ref/valid.exr", "/dev/zero", "is not a regular file (a character device)");
    expectRefused("compare ref/valid.png ref/valid.png --mask folder.csv", "folder.csv", "is a folder");
}

TEST_F(SpecialFiles, ASweepFile) { expectRefused("batch fifo.json --out o", "fifo.json", kFifo); }

// A regular HDF5 file whose /cube keeps its values in a FIFO (external storage, issue 30 class 6):
// HDF5 would open the FIFO when the values are read and block for ever. Every reader of a cube
// refuses it from the dataset's properties, under the timeout.
TEST_F(SpecialFiles, AnHdf5CubeWhoseValuesAreInAFifo) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    hid_t f = H5Fcreate((dir_ / "external.h5").c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    const hsize_t dims[3] = {2, 2, 31}, bands = 31;
    hid_t space = H5Screate_simple(3, dims, nullptr), wlSpace = H5Screate_simple(1, &bands, nullptr);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    ASSERT_GE(H5Pset_external(dcpl, (dir_ / "fifo.exr").c_str(), 0, 2 * 2 * 31 * 4), 0);
    hid_t cube = H5Dcreate2(f, "cube", H5T_IEEE_F32LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    hid_t wl = H5Dcreate2(f, "wavelength_nm", H5T_IEEE_F64LE, wlSpace, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(cube, 0);
    ASSERT_GE(wl, 0);
    std::vector<double> nm;
    for (int i = 0; i < 31; ++i) nm.push_back(400 + 10 * i);
    ASSERT_GE(H5Dwrite(wl, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, nm.data()), 0);
    for (hid_t d : {cube, wl}) H5Dclose(d);
    for (hid_t s : {space, wlSpace}) H5Sclose(s);
    H5Pclose(dcpl);
    H5Fclose(f);

    const std::string what = "external.h5: /cube: keeps its values in 1 external file";
    expectRefused("compare external.h5 ref/valid.exr", "fifo.exr", what);
    expectRefused("compare ref/valid.exr external.h5", "fifo.exr", what);
    expectRefused("capture external.h5 --sensor mono_silicon --out o", "fifo.exr", what);
    write("external-texture.json", scene(R"("textures": {"diffuse": "external.h5"})"));
    expectRefused("render external-texture.json --out o", "materials.m.textures.diffuse", what);
}

}  // namespace

// Standard input has no size to check first: a scene read from it is held to the same 256 MiB as a
// scene file, and /dev/zero ends at once instead of growing for ever (issue 51, class 5).
TEST_F(SpecialFiles, AStandardInputWithoutEnd) {
    expectRefused("render - --out o < /dev/zero", "<stdin>", "the scene read from standard input is over 256 MiB");
    EXPECT_FALSE(fs::exists(dir_ / "o"));
}

// Started with a standard stream closed (`2>&-`), the next file opened would take its descriptor
// and receive what is written to it — the progress lines into the cube. Each closed one is opened
// on /dev/null first (issue 51, class 6): the cube reads back whole and equals a render's with the
// streams open.
TEST_F(SpecialFiles, ClosedStandardStreams) {
    const std::string cmd = "cd '" + dir_.string() + "' && " METAMER_BINARY
                            " render valid.json --out closed --write cube --progress 2>&- >/dev/null; echo $? > status";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    std::ifstream status(dir_ / "status");
    int code = -1;
    status >> code;
    EXPECT_EQ(code, 0);
    const test::CliRun same = run("compare closed/valid.exr ref/valid.exr");
    EXPECT_EQ(same.code, 0) << same.output;
}
