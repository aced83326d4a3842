#include "app/capture_command.h"
#include "app/cli_checks.h"

#include "core/error.h"
#include "sensor/capture_files.h"
#include "spectral/library.h"

#include <cstdio>

namespace metamer {

CLI::App* addCaptureCommand(CLI::App& app, CaptureArgs& a) {
    CLI::App* c = app.add_subcommand("capture", "what a simulated camera sensor records from a rendered cube: a raw "
                                                "mosaic with shot, read and fixed-pattern noise (docs/sensor.md)");
    c->add_option("cube", a.cube, "a spectral radiance cube (EXR, HDF5 or ENVI), as metamer render writes it")->required();
    c->add_option("--sensor", a.sensor, "a sensor file (.json), or a library sensor's name (spectra/sensors/)")->required();
    c->add_option("--out,-o", a.out, "output folder (created if missing)")->check(outputFolder())->capture_default_str();
    c->add_option("--seed", a.seed, "the temporal noise's seed (the fixed pattern has its own, in the sensor file)")
        ->capture_default_str();
    c->add_option("--frame", a.frame, "the first frame's number: (seed, frame) picks one exposure's noise")
        ->capture_default_str();
    c->add_option("--frames", a.frames, "frames to capture, numbered from --frame")->check(CLI::Range(1, 100000))
        ->capture_default_str();
    c->add_option("--exposure", a.exposure, "exposure time in seconds, overriding the sensor file's");
    c->add_flag("--no-noise", a.noNoise, "the expected values, rounded: no shot, read or fixed-pattern noise drawn");
    c->add_option("--illuminant", a.illuminant,
                  "the scene's light, a library spectrum (illuminants/A): the image processor's white balance and "
                  "colour correction, and the DNG's, overriding the sensor file's processor.illuminant (docs/camera.md)");
    return c;
}

int runCapture(const CaptureArgs& a) {
    const SpectrumLibrary library;
    CaptureRequest request;
    request.cube = a.cube;
    request.sensor = a.sensor;
    request.out = a.out;
    request.seed = a.seed;
    request.frame = a.frame;
    request.frames = a.frames;
    request.exposure = a.exposure;
    request.noise = !a.noNoise;
    if (!a.illuminant.empty()) request.illuminant = a.illuminant;
    captureToFiles(request, library, [](const std::string& line) { std::printf("%s\n", line.c_str()); });
    return 0;
}

}  // namespace metamer
