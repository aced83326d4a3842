// `metamer capture`'s files (docs/sensor.md, "Outputs"), shared by the command and by `metamer
// batch` jobs that name a sensor: a cube file in, per frame a raw PNG, a DNG (RGB Bayer sensors)
// and the metadata, and once the expected electrons.
// Tests: tests/python/test_sensor.py, tests/batch_test.cpp.
#pragma once

#include "sensor/capture.h"
#include "spectral/cube.h"
#include "spectral/library.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace metamer {

struct CaptureRequest {
    std::filesystem::path cube;   // a spectral radiance cube file
    // The name the metadata and errors give the cube, when `cube` is where a render's cube waits
    // to be renamed into place (render --sensor); empty: `cube`.
    std::filesystem::path cubeName;
    std::string sensor;           // a sensor file, or a library sensor's name
    std::filesystem::path out;    // the folder the files go to
    std::string stem;             // the files' stem; empty: the cube's
    uint64_t seed = 0, frame = 0;
    int frames = 1;
    std::optional<double> exposure;
    bool noise = true;
    // The scene's light for the image processor (a library spectrum), instead of the sensor file's
    // processor.illuminant; errors name `illuminantKey` (the CLI's flag or Python's keyword).
    std::optional<std::string> illuminant;
    std::string illuminantKey = "--illuminant";
};

// The sensor of `request`, read, with the request's illuminant (if any) as its processor's.
SensorSpec readCaptureSensor(const CaptureRequest& request, const SpectrumLibrary& library);

// A capture's numbers, for the CLI and Python alike (`prefix` "--" names the CLI's flags, "" the
// keywords): an exposure in (0, 10⁶] s, 1 … 100 000 frames, numbered from `frame` without passing
// 2⁶⁴ − 1. Input errors naming the flag or keyword.
void checkCaptureNumbers(std::optional<double> exposure, uint64_t frame, int frames, const std::string& prefix);

struct CaptureFiles {
    std::vector<std::filesystem::path> files;  // as they are named once committed, in order
    std::vector<std::string> lines;            // what was written, a line per file set, for the log
    double exposure_s = 0.0;
    bool autoExposed = false;
};

// A spectral radiance cube from a file (EXR, HDF5 or ENVI); a reflectance cube is an input error
// naming the file: a sensor captures radiance.
SpectralCube readRadianceCube(const std::filesystem::path& file);


// Among the files a render wrote, its spectral cube (EXR, HDF5 or ENVI, named <stem>.<ext>, not
// <stem>.xyz.exr); a runtime error when there is none.
std::filesystem::path renderedCube(const std::vector<std::filesystem::path>& written);

class AtomicOutput;
class StagingFolder;

// Captures `request.frames` frames into `staging` (request.out is not used): nothing is in place
// until the caller commits the folder, with the render's files when there are some
// (io/atomic_file.h, commitTogether). Errors name the cube as request.cubeName.
CaptureFiles stageCapture(const CaptureRequest& request, const SpectrumLibrary& library, StagingFolder& staging);

// The files of a capture whose expected electrons are already computed (by expectedElectrons with
// request.exposure and request.noise, from `sensor`), named request.cubeName in the metadata: the
// Python module's `out`, which has computed them for its arrays.
CaptureFiles stageCaptureFiles(const ExpectedElectrons& expected, const SensorSpec& sensor, const CaptureRequest& request,
                               const SpectrumLibrary& library, StagingFolder& staging);

// The same for a render's cube before the render's files are renamed into place (`files`, as a
// render's BeforeCommitHook receives them: render/render_job_spec.h): the cube is read where it
// waits and named by its final path, and what is staged is committed with the render, so `render
// --sensor` and a sweep job with a sensor put all their files in place together or none.
CaptureFiles stageCaptureOfRender(CaptureRequest request, const std::vector<AtomicOutput*>& files,
                                  const SpectrumLibrary& library, StagingFolder& staging);

// Captures `request.frames` frames into request.out, every file put in place together once all
// are written (a failure at any frame leaves the folder as it was); `log` hears one line per file
// set, after the commit.
CaptureFiles captureToFiles(const CaptureRequest& request, const SpectrumLibrary& library,
                            const std::function<void(const std::string&)>& log = {});

}  // namespace metamer
