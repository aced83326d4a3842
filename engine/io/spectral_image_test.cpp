#include "io/spectral_image.h"

#include "io/envi_cube.h"
#include "io/hdf5_cube.h"

#include "support/cubes.h"
#include "support/temp_folder.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <random>
#include <unistd.h>

using namespace metamer;
namespace fs = std::filesystem;
using test::expectBitExact;
using test::randomCube;

namespace {

class SpectralImageFile : public test::TempFolderTest {};

}  // namespace

TEST_F(SpectralImageFile, CubeFormatOfGoesByContentsNotName) {
    const SpectralCube cube = randomCube(3, 2, Grid{400, 700, 20}, 1);
    writeSpectralExr(dir / "a.exr", cube);
    writeHdf5Cube(dir / "a.h5", cube);
    writeEnviCube(dir / "a.hdr", cube);
    EXPECT_EQ(cubeFormatOf(dir / "a.exr"), CubeFormat::Exr);
    EXPECT_EQ(cubeFormatOf(dir / "a.h5"), CubeFormat::Hdf5);
    EXPECT_EQ(cubeFormatOf(dir / "a.hdr"), CubeFormat::Envi);
    EXPECT_EQ(cubeFormatOf(dir / "a.img"), CubeFormat::Envi);
    // Misnamed files are still what they hold.
    fs::copy_file(dir / "a.h5", dir / "h5.exr");
    fs::copy_file(dir / "a.exr", dir / "exr.h5");
    EXPECT_EQ(cubeFormatOf(dir / "h5.exr"), CubeFormat::Hdf5);
    EXPECT_EQ(cubeFormatOf(dir / "exr.h5"), CubeFormat::Exr);
    // ENVI data with other extensions, and the <name>.hdr spelling.
    fs::copy_file(dir / "a.img", dir / "b.raw");
    fs::copy_file(dir / "a.hdr", dir / "b.hdr");
    fs::copy_file(dir / "a.img", dir / "c.dat");
    fs::copy_file(dir / "a.hdr", dir / "c.dat.hdr");
    EXPECT_EQ(cubeFormatOf(dir / "b.raw"), CubeFormat::Envi);
    EXPECT_EQ(cubeFormatOf(dir / "c.dat"), CubeFormat::Envi);
    // Not cubes.
    fs::copy_file(dir / "a.img", dir / "lonely.img");
    EXPECT_EQ(cubeFormatOf(dir / "lonely.img"), std::nullopt);
    std::ofstream(dir / "text.txt") << "hello";
    EXPECT_EQ(cubeFormatOf(dir / "text.txt"), std::nullopt);
    std::ofstream(dir / "empty.exr");
    EXPECT_EQ(cubeFormatOf(dir / "empty.exr"), std::nullopt);
    EXPECT_EQ(cubeFormatOf(dir / "missing.exr"), std::nullopt);
    EXPECT_EQ(cubeFormatOf(dir), std::nullopt);
    EXPECT_EQ(cubeFormatOf("/dev/zero"), std::nullopt);
    EXPECT_STREQ(cubeFormatName(CubeFormat::Hdf5), "HDF5");
}

TEST_F(SpectralImageFile, ReadSpectralImageReadsTheSameCubeFromEveryFormat) {
    const SpectralCube cube = randomCube(7, 5, Grid{400, 520, 10}, 2);
    writeSpectralExr(dir / "a.exr", cube);
    writeHdf5Cube(dir / "a.h5", cube, {.gzipLevel = 6});
    writeEnviCube(dir / "a.hdr", cube, {.interleave = EnviInterleave::Bip});
    for (const char* name : {"a.exr", "a.h5", "a.hdr", "a.img"}) {
        SCOPED_TRACE(name);
        const SpectralImage image = readSpectralImage(dir / name);
        EXPECT_EQ(image.component, SpectralComponent::Emissive);
        expectBitExact(cube, image.cube);
    }
    writeHdf5Cube(dir / "r.h5", cube, {.component = SpectralComponent::Reflective});
    writeEnviCube(dir / "r.hdr", cube, {.component = SpectralComponent::Reflective});
    EXPECT_EQ(readSpectralImage(dir / "r.h5").component, SpectralComponent::Reflective);
    EXPECT_EQ(readSpectralImage(dir / "r.img").component, SpectralComponent::Reflective);
}

TEST_F(SpectralImageFile, AnythingElseIsAnInputErrorNamingTheFile) {
    auto expectInputError = [](const fs::path& p, const std::string& fragment) {
        try {
            readSpectralImage(p);
            ADD_FAILURE() << "expected an error for " << p;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadInput) << e.what();
            EXPECT_EQ(e.where().file, p.string()) << e.what();
            EXPECT_NE(e.message().find(fragment), std::string::npos) << e.what();
        }
    };
    std::ofstream(dir / "cube.png") << "\x89PNG\r\n\x1a\n not a cube";
    expectInputError(dir / "cube.png", "not a spectral image");
    expectInputError(dir / "missing.h5", "not found");
    expectInputError(dir, "is a folder, not a file");
    expectInputError("/dev/zero", "not a regular file");
}
