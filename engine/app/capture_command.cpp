#include "app/capture_command.h"
#include "app/cli_checks.h"

#include "core/error.h"
#include "core/json.h"
#include "io/atomic_file.h"
#include "io/dng_file.h"
#include "io/image_file.h"
#include "io/spectral_image.h"
#include "sensor/capture.h"
#include "sensor/sensor_colour.h"
#include "spectral/library.h"

#include <fmt/format.h>

#include <cstdio>

namespace metamer {

namespace fs = std::filesystem;

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
    return c;
}

int runCapture(const CaptureArgs& a) {
    if (a.exposure && !(*a.exposure > 0.0 && *a.exposure <= 1e6))
        failInput(Where{"--exposure"}, "expected an exposure time in seconds, > 0 and at most 10⁶, got {:g}", *a.exposure);
    const SpectrumLibrary library;
    const SensorSpec sensor = readSensor(sensorFile(a.sensor, library), library);
    const SpectralImage image = readSpectralImage(a.cube);
    if (image.component != SpectralComponent::Emissive)
        failInput(Where{a.cube}, "the cube holds reflectance; a sensor captures spectral radiance (metamer render's cube)");
    const SpectralCube& cube = image.cube;
    const ExpectedElectrons e = expectedElectrons(cube, sensor, a.exposure, !a.noNoise);
    // An RGB Bayer sensor's frames are also DNGs, with the colour data a raw converter needs.
    const std::optional<SensorColour> colour = sensorColour(sensor, library);
    const std::string stem = fs::path(a.cube).stem().string();
    const fs::path out(a.out);

    // The truth: expected electrons per pixel, float.
    std::vector<float> electrons(e.electrons.begin(), e.electrons.end());
    writeImage(out / (stem + ".electrons.exr"), ImageFile{e.width, e.height, {"electrons"}, {}}, electrons);
    nlohmann::ordered_json cfa = nlohmann::ordered_json::array();
    for (const auto& row : sensor.cfa) {
        nlohmann::ordered_json r = nlohmann::ordered_json::array();
        for (int c : row) r.push_back(sensor.channels[size_t(c)]);
        cfa.push_back(r);
    }
    for (int f = 0; f < a.frames; ++f) {
        const uint64_t frame = a.frame + uint64_t(f);
        const std::vector<uint16_t> raw = digitize(e.electrons, e.width, sensor, CaptureNoise{!a.noNoise, a.seed, frame});
        const std::string name = a.frames == 1 ? stem + ".raw" : fmt::format("{}.raw.{}", stem, frame);
        std::vector<uint16_t> counts(raw.begin(), raw.end());
        writeImage(out / (name + ".png"), ImageFile{e.width, e.height, {"Y"}, {}}, counts, 16);
        if (colour) {
            DngRaw dng;
            dng.width = e.width;
            dng.height = e.height;
            dng.pixels = raw.data();
            dng.cfa = colour->cfa;
            dng.blackLevel = sensor.blackLevel_dn;
            dng.whiteLevel = sensor.whiteLevel();
            dng.colorMatrix1 = colour->xyzToCamera;
            dng.asShotNeutral = colour->asShotNeutral;
            dng.model = "Metamer " + sensor.file.stem().string();
            dng.description = sensor.description;
            writeDng(out / (name + ".dng"), dng);
        }
        nlohmann::ordered_json meta = {
            {"raw", name + ".png"},
            {"dng", colour ? nlohmann::ordered_json(name + ".dng") : nlohmann::ordered_json(nullptr)},
            {"electrons", stem + ".electrons.exr"},
            {"cube", a.cube},
            {"sensor", sensor.file.string()},
            {"sensor_description", sensor.description},
            {"width", e.width},
            {"height", e.height},
            {"channels", sensor.channels},
            {"cfa", cfa},
            {"cfa_name", sensor.cfaName},
            {"units", "digital numbers (DN); raw = round(K·electrons) + black, clipped to 0 … white"},
            {"black_level_dn", sensor.blackLevel_dn},
            {"white_level_dn", sensor.whiteLevel()},
            {"adc_bits", sensor.adcBits},
            {"conversion_gain_dn_per_e", sensor.gain_dn_per_e},
            {"full_well_e", sensor.fullWell_e},
            {"read_noise_e", sensor.readNoise_e},
            {"exposure_s", jsonNumber(e.exposure_s)},
            {"auto_exposed", e.autoExposed},
            {"noise", !a.noNoise},
            {"seed", a.seed},
            {"frame", frame},
            {"fpn_seed", sensor.fpnSeed},
            {"quantum_efficiency", sensor.qeSource},
        };
        if (colour) {
            meta["xyz_to_camera_d65"] = colour->xyzToCamera;
            meta["as_shot_neutral"] = colour->asShotNeutral;
            meta["characterization_rms_delta_e2000"] = colour->rmsDeltaE2000;
        }
        writeFileAtomically(out / (name + ".json"), meta.dump(2) + "\n");
        std::printf("wrote %s (%d×%d, %s, exposure %.6g s%s, %s)\n", (out / (name + ".png")).string().c_str(), e.width,
                    e.height, sensor.cfaName.c_str(), e.exposure_s, e.autoExposed ? " (auto)" : "",
                    a.noNoise ? "no noise" : fmt::format("seed {}, frame {}", a.seed, frame).c_str());
    }
    std::printf("wrote %s (expected electrons per pixel, float)\n", (out / (stem + ".electrons.exr")).string().c_str());
    return 0;
}

}  // namespace metamer
