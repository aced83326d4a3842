#include "sensor/capture_files.h"

#include "color/display_profile.h"
#include "core/error.h"
#include "core/json.h"
#include "io/atomic_file.h"
#include "io/dng_file.h"
#include "io/image_file.h"
#include "io/spectral_image.h"
#include "sensor/capture.h"
#include "sensor/sensor_colour.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <limits>
#include <unistd.h>

namespace metamer {

namespace fs = std::filesystem;

SpectralCube readRadianceCube(const fs::path& file) {
    SpectralImage image = readSpectralImage(file);
    if (image.component != SpectralComponent::Emissive)
        failInput(Where{file.string()}, "the cube holds reflectance; a sensor captures spectral radiance (metamer render's cube)");
    return std::move(image.cube);
}

fs::path renderedCube(const std::vector<fs::path>& written) {
    for (const fs::path& f : written)
        if (cubeFormatOf(f) && f.stem().extension().empty()) return f;
    failRuntime("the render wrote no spectral cube for the sensor to capture");
}

void checkCaptureNumbers(std::optional<double> exposure, uint64_t frame, int frames, const std::string& prefix) {
    if (exposure && !(*exposure > 0.0 && *exposure <= 1e6))
        failInput(Where{prefix + "exposure"}, "expected an exposure time in seconds, > 0 and at most 10⁶, got {:g}", *exposure);
    if (frames < 1 || frames > 100000) failInput(Where{prefix + "frames"}, "expected 1 … 100000 frames, got {}", frames);
    // The last frame's number must fit too: frame + frames − 1 would wrap to 0.
    if (frame > std::numeric_limits<uint64_t>::max() - uint64_t(frames - 1))
        failInput(Where{prefix + "frame"}, "{} + {} frames passes the last frame number, {}", frame, frames,
                  std::numeric_limits<uint64_t>::max());
}

SensorSpec readCaptureSensor(const CaptureRequest& a, const SpectrumLibrary& library) {
    SensorSpec sensor = readSensor(sensorFile(a.sensor, library), library);
    if (a.illuminant) {
        library.get(*a.illuminant, Where{a.illuminantKey});  // an unknown name, with a suggestion
        sensor.processor.illuminant = *a.illuminant;
    }
    return sensor;
}

CaptureFiles stageCapture(const CaptureRequest& a, const SpectrumLibrary& library, StagingFolder& staging) {
    checkCaptureNumbers(a.exposure, a.frame, a.frames, "--");
    const fs::path& cubeName = a.cubeName.empty() ? a.cube : a.cubeName;
    const SensorSpec sensor = readCaptureSensor(a, library);  // its mistakes before the cube's
    SpectralCube cube;
    try {
        cube = readRadianceCube(a.cube);
    } catch (const Error& e) {
        rethrowNaming(e, a.cube.string(), cubeName.string());
    }
    requireRadiance(cube, Where{cubeName.string()});
    CaptureRequest named = a;
    named.cubeName = cubeName;
    return stageCaptureFiles(expectedElectrons(cube, sensor, a.exposure, a.noise), sensor, named, library, staging);
}

CaptureFiles stageCaptureFiles(const ExpectedElectrons& e, const SensorSpec& sensor, const CaptureRequest& a,
                               const SpectrumLibrary& library, StagingFolder& staging) {
    const fs::path& cubeName = a.cubeName.empty() ? a.cube : a.cubeName;
    CaptureFiles written;
    written.exposure_s = e.exposure_s;
    written.autoExposed = e.autoExposed;
    // An RGB Bayer sensor's frames are also DNGs, with the colour data a raw converter needs.
    const std::optional<SensorColour> colour = sensorColour(sensor, library);
    // A monochrome sensor's frames are DNGs too (LinearRaw); a multispectral tile has no DNG form.
    const bool dngWritten = colour || sensor.cfaName == "mono";
    const std::string stem = a.stem.empty() ? cubeName.stem().string() : a.stem;
    auto stage = [&](const std::string& filename) {
        written.files.push_back(staging.finalPath(filename));
        return staging.stage(filename);
    };

    // The truth: expected electrons per pixel, float.
    const std::vector<double> recorded = e.recordedMean();
    std::vector<float> electrons(recorded.begin(), recorded.end());
    writeImage(stage(stem + ".electrons.exr"), ImageFile{e.width, e.height, {"electrons"}, {}}, electrons);
    nlohmann::ordered_json cfa = nlohmann::ordered_json::array();
    for (const auto& row : sensor.cfa) {
        nlohmann::ordered_json r = nlohmann::ordered_json::array();
        for (int c : row) r.push_back(sensor.channels[size_t(c)]);
        cfa.push_back(r);
    }
    // The developed frames' PNG and its colour tag (a CRT's ICC profile is built by Little CMS):
    // once, for every frame.
    ImageFile developedImage{e.width, e.height, {"R", "G", "B"}, {}};
    if (colour) {
        DisplayColourTag tag = displayColourTag(colour->processor.display);
        if (tag.srgbChunk) developedImage.attributes.push_back({"oiio:ColorSpace", "sRGB"});
        developedImage.iccProfile = std::move(tag.iccProfile);
    }
    for (int f = 0; f < a.frames; ++f) {
        const uint64_t frame = a.frame + uint64_t(f);
        const std::vector<uint16_t> raw = digitize(e, sensor, CaptureNoise{a.noise, a.seed, frame});
        const std::string name = a.frames == 1 ? stem + ".raw" : fmt::format("{}.raw.{}", stem, frame);
        std::vector<uint16_t> counts(raw.begin(), raw.end());
        writeImage(stage(name + ".png"), ImageFile{e.width, e.height, {"Y"}, {}}, counts, 16);
        // An RGB Bayer frame developed by the image processor, and its white balance's neutral:
        // the DNG's AsShotNeutral, so a raw converter balances as the processor did.
        std::optional<DevelopedImage> developed;
        if (colour && developable(e.width, e.height)) {
            RawFrame f{e.width, e.height, raw.data(), sensor.blackLevel_dn, double(sensor.whiteLevel()), {}};
            for (size_t i = 0; i < 4; ++i) f.cfa[i] = colour->cfa[i];
            developed = develop(f, sensor.processor, colour->processor, Where{sensor.file.string(), "processor"});
            const DisplayModel& display = colour->processor.display;
            writeImage(stage(name + "." + display.name + ".png"), developedImage, encodeCounts(*developed, display),
                       display.bits);
        }
        if (dngWritten) {
            DngRaw dng;
            dng.width = e.width;
            dng.height = e.height;
            dng.pixels = raw.data();
            dng.monochrome = !colour;
            if (colour) {
                dng.cfa = colour->cfa;
                dng.colorMatrix1 = colour->processor.dngColorMatrix;
                const glm::dvec3 n = developed ? developed->neutral : colour->processor.illuminantNeutral;
                dng.asShotNeutral = {n.x, n.y, n.z};
            }
            dng.blackLevel = sensor.blackLevel_dn;
            dng.whiteLevel = sensor.whiteLevel();
            dng.model = "Metamer " + sensor.file.stem().string();
            dng.description = sensor.description;
            writeDng(stage(name + ".dng"), dng);
        }
        nlohmann::ordered_json meta = {
            {"raw", name + ".png"},
            {"dng", dngWritten ? nlohmann::ordered_json(name + ".dng") : nlohmann::ordered_json(nullptr)},
            {"electrons", stem + ".electrons.exr"},
            {"cube", cubeName.string()},
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
            {"noise", a.noise},
            {"seed", a.seed},
            {"frame", frame},
            {"fpn_seed", sensor.fpnSeed},
            {"quantum_efficiency", sensor.qeSource},
        };
        if (colour) {
            const ProcessorSpec& p = sensor.processor;
            const ProcessorColour& c = colour->processor;
            // A frame narrower than the CFA's tile is not developed (nothing to demosaic): its
            // DNG has the illuminant's neutral.
            const glm::dvec3 n = developed ? developed->neutral : c.illuminantNeutral;
            const glm::dvec3 gains = developed ? developed->gains : glm::dvec3(std::max({n.x, n.y, n.z})) / n;
            meta["developed"] = developed ? nlohmann::ordered_json(name + "." + c.display.name + ".png")
                                          : nlohmann::ordered_json(nullptr);
            meta["xyz_to_camera_d65"] = c.dngColorMatrix;
            meta["as_shot_neutral"] = {n.x, n.y, n.z};
            meta["characterization_rms_delta_e2000"] = c.rmsDeltaE2000;
            nlohmann::ordered_json correction = nlohmann::ordered_json::array();
            for (const glm::dvec3& column : c.toXyz.columns) correction.push_back({column.x, column.y, column.z});
            meta["processor"] = {
                {"white_balance", whiteBalanceName(p.whiteBalance)},
                {"illuminant", p.illuminant},
                {"demosaic", p.demosaic == DemosaicMethod::Bilinear ? "bilinear" : "malvar2004"},
                {"colour_correction", p.correction == CorrectionForm::Linear ? "linear" : "root-polynomial"},
                {"correction_columns", correction},
                {"adaptation", adaptationName(p.adaptation)},
                {"exposure", p.exposure},
                {"white_balance_gains", {gains.x, gains.y, gains.z}},
                {"colorchecker_delta_e2000", c.patchDeltaE2000},
                {"display", c.display.name},
                {"bits", c.display.bits},
            };
        }
        writeFileAtomically(stage(name + ".json"), meta.dump(2) + "\n");
        written.lines.push_back(fmt::format("wrote {}{} ({}×{}, {}, exposure {:.6g} s{}, {})",
                                            staging.finalPath(name + ".png").string(),
                                            developed ? fmt::format(", .dng and .{}.png", colour->processor.display.name)
                                            : dngWritten ? std::string(colour ? " and .dng (too small to develop)" : " and .dng")
                                                         : std::string(),
                                            e.width, e.height, sensor.cfaName, e.exposure_s,
                                            e.autoExposed ? " (auto)" : "",
                                            a.noise ? fmt::format("seed {}, frame {}", a.seed, frame)
                                                    : std::string("no noise")));
    }
    written.lines.push_back(fmt::format("wrote {} (expected electrons per pixel, float)",
                                        staging.finalPath(stem + ".electrons.exr").string()));
    return written;
}

CaptureFiles stageCaptureOfRender(CaptureRequest request, const std::vector<AtomicOutput*>& files,
                                  const SpectrumLibrary& library, StagingFolder& staging) {
    // The render's files under their final names in a folder of their own (hard links to the
    // temporaries, or copies), so the cube is found and read as it will be: an ENVI header finds
    // its data beside it. The folder goes when this returns.
    StagingFolder pending(staging.target(), "render");
    std::vector<fs::path> named;
    for (const AtomicOutput* f : files) {
        const fs::path at = pending.stage(f->finalPath().filename().string());
        if (::link(f->tempPath().c_str(), at.c_str()) != 0) fs::copy_file(f->tempPath(), at);
        named.push_back(at);
    }
    // An ENVI cube is named by its header, as the render's own lines name it.
    std::stable_partition(named.begin(), named.end(), [](const fs::path& p) { return p.extension() == ".hdr"; });
    const fs::path cube = renderedCube(named);
    request.cube = cube;
    for (const AtomicOutput* f : files)
        if (f->finalPath().filename() == cube.filename()) request.cubeName = f->finalPath();
    return stageCapture(request, library, staging);
}

CaptureFiles captureToFiles(const CaptureRequest& a, const SpectrumLibrary& library,
                            const std::function<void(const std::string&)>& log) {
    StagingFolder staging(a.out, "capture");
    CaptureFiles written = stageCapture(a, library, staging);
    commitTogether({}, {&staging});
    if (log)
        for (const std::string& line : written.lines) log(line);
    return written;
}

}  // namespace metamer
