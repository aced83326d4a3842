#include "sensor/sensor_spec.h"

#include "sensor/sensor_colour.h"

#include "core/error.h"
#include "support/temp_folder.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

using namespace metamer;

namespace {

class SensorFile : public test::TempFolderTest {
protected:
    nlohmann::ordered_json base() const {
        return nlohmann::ordered_json::parse(R"({
          "optics": {"f_number": 4, "transmittance": 0.9},
          "pixel": {"pitch_um": 4.78},
          "quantum_efficiency": {"table": "cameras/nikon_d5100", "peak": 0.45},
          "cfa": "RGGB", "exposure_s": 0.01, "full_well_e": 30000, "conversion_gain_dn_per_e": 0.5
        })");
    }
    SensorSpec read(const nlohmann::ordered_json& j) {
        const auto path = dir / "sensor.json";
        std::ofstream(path) << j.dump(2);
        return readSensor(path, library);
    }
    // The input error `j` raises: its key and text.
    std::string error(const nlohmann::ordered_json& j) {
        try {
            read(j);
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadInput);
            return e.where().key + ": " + e.message();
        }
        return "(no error)";
    }
    const SpectrumLibrary library;
};

}  // namespace

TEST_F(SensorFile, TheBundledSensorReads) {
    const SensorSpec s = readSensor(library.root() / "sensors" / "aps_c_rggb.json", library);
    EXPECT_EQ(s.channels, (std::vector<std::string>{"r", "g", "b"}));
    EXPECT_EQ(s.cfa, (std::vector<std::vector<int>>{{0, 1}, {1, 2}}));
    EXPECT_EQ(s.channelAt(0, 0), 0);
    EXPECT_EQ(s.channelAt(3, 3), 2);
    EXPECT_EQ(s.whiteLevel(), 16383u);
    EXPECT_FALSE(s.exposure_s.has_value());  // "auto"
    double peak = 0.0;
    for (const Spectrum& q : s.quantumEfficiency)
        for (double v : q.values) peak = std::max(peak, v);
    EXPECT_NEAR(peak, 0.45, 1e-15);
}

TEST_F(SensorFile, EveryBundledSensorReads) {
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(library.root() / "sensors"))
        if (e.path().extension() == ".json") {
            const SensorSpec s = readSensor(e.path(), library);
            EXPECT_FALSE(s.description.empty()) << e.path();
            ++n;
        }
    EXPECT_EQ(n, 3);
    const SensorSpec mono = readSensor(sensorFile("mono_silicon", library), library);
    EXPECT_EQ(mono.cfaName, "mono");
    EXPECT_EQ(mono.channelAt(5, 7), 0);
    const SensorSpec msfa = readSensor(sensorFile("msfa_4band", library), library);
    EXPECT_EQ(msfa.channels, (std::vector<std::string>{"b460", "g530", "y600", "r670"}));
    EXPECT_EQ(msfa.channelAt(1, 1), 3);
}

TEST_F(SensorFile, PatternsByLettersRowsAndMono) {
    auto j = base();
    j["cfa"] = "GBRG";
    EXPECT_EQ(read(j).cfa, (std::vector<std::vector<int>>{{1, 2}, {0, 1}}));
    j["cfa"] = nlohmann::ordered_json::parse(R"([["g", "r", "g"], ["b", "g", "b"]])");
    EXPECT_EQ(read(j).cfa, (std::vector<std::vector<int>>{{1, 0, 1}, {2, 1, 2}}));
}

TEST_F(SensorFile, MistakesNameTheKey) {
    auto with = [&](const char* key, nlohmann::ordered_json v) {
        auto j = base();
        j[key] = std::move(v);
        return error(j);
    };
    EXPECT_NE(with("cfa", "RGBG").find("cfa: 'RGBG' is not one of RGGB, BGGR, GRBG, GBRG, mono; did you mean 'RGGB'?"),
              std::string::npos);
    EXPECT_NE(with("cfa", "mono").find("cfa: a monochrome sensor has one channel; the quantum-efficiency table has 3"),
              std::string::npos);
    EXPECT_NE(with("cfa", nlohmann::ordered_json::parse(R"([["r", "x"]])")).find("cfa.0.1: unknown channel 'x'"),
              std::string::npos);
    EXPECT_NE(with("exposure_s", "long").find("exposure_s: expected an exposure time in seconds or \"auto\""),
              std::string::npos);
    EXPECT_NE(with("adc_bits", 17).find("adc_bits"), std::string::npos);
    EXPECT_NE(with("fpn_seed", 1.5).find("fpn_seed: expected a whole number"), std::string::npos);
    EXPECT_NE(with("exposure", 1).find("exposure: "), std::string::npos);  // a typo, with a suggestion
    auto j = base();
    j.erase("pixel");
    EXPECT_NE(error(j).find("pixel: missing required key"), std::string::npos) << error(j);
    j = base();
    j["quantum_efficiency"]["table"] = "cameras/nikon";
    EXPECT_NE(error(j).find("quantum_efficiency.table"), std::string::npos) << error(j);
    j = base();
    j["optics"]["transmittance"] = 1.5;
    EXPECT_NE(error(j).find("optics.transmittance"), std::string::npos) << error(j);
    j = base();  // issue 51, class 2: 10⁻³⁰⁰ mm made every pixel NaN, blamed on the cube
    j["optics"]["cos4_focal_length_mm"] = 1e-300;
    EXPECT_NE(error(j).find("optics.cos4_focal_length_mm"), std::string::npos) << error(j);
    j = base();
    j["quantum_efficiency"]["includes_fill_factor"] = "yes";
    EXPECT_NE(error(j).find("quantum_efficiency.includes_fill_factor: expected true (EMVA 1288"), std::string::npos)
        << error(j);
}

// Issue 48, item 4: the QE is EMVA 1288's (per pixel area, the fill factor included) unless the file
// says it is the photodiode's; only then does the fill factor scale the area.
TEST_F(SensorFile, TheFillFactorScalesOnlyAPhotodiodesQe) {
    auto j = base();
    j["pixel"]["fill_factor"] = 0.6;
    const SensorSpec emva = read(j);
    EXPECT_TRUE(emva.qeIncludesFillFactor);
    EXPECT_DOUBLE_EQ(emva.pixelArea_m2(), emva.pitch_um * emva.pitch_um * 1e-12);
    j["quantum_efficiency"]["includes_fill_factor"] = false;
    const SensorSpec diode = read(j);
    EXPECT_DOUBLE_EQ(diode.pixelArea_m2(), emva.pixelArea_m2() * 0.6);
}

// Channels whose quantum efficiencies are linearly dependent leave the ColorChecker fit singular:
// an input error at the sensor's quantum_efficiency (issue 51, class 2), not NaN in the DNG.
TEST_F(SensorFile, LinearlyDependentChannelsHaveNoColourMatrix) {
    std::ofstream(dir / "alike.csv") << "wavelength_nm,r,g,b\n380,0.1,0.1,0.1\n550,0.5,0.5,0.5\n780,0.1,0.1,0.1\n";
    auto j = base();
    j["quantum_efficiency"]["table"] = "alike.csv";
    const SensorSpec s = read(j);
    try {
        sensorColour(s, library);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.where().key, "quantum_efficiency");
        EXPECT_NE(e.message().find("linearly dependent"), std::string::npos) << e.message();
    }
    EXPECT_TRUE(sensorColour(readSensor(library.root() / "sensors" / "aps_c_rggb.json", library), library).has_value());
}

TEST_F(SensorFile, TheProcessorIsReadWithItsKeysAndNamesChecked) {
    auto processor = [&](const char* text) {
        auto j = base();
        j["processor"] = nlohmann::ordered_json::parse(text);
        return j;
    };
    const SensorSpec s = read(processor(R"({"white_balance": "patch", "patch": [10, 20, 30, 40],
        "illuminant": "illuminants/A", "demosaic": "bilinear", "colour_correction": "root-polynomial",
        "adaptation": "cat16", "exposure": 2, "display": "crt", "bits": 16})"));
    EXPECT_EQ(s.processor.whiteBalance, WhiteBalance::Patch);
    EXPECT_EQ(s.processor.patch, (std::array<int, 4>{10, 20, 30, 40}));
    EXPECT_EQ(s.processor.illuminant, "illuminants/A");
    EXPECT_EQ(s.processor.demosaic, DemosaicMethod::Bilinear);
    EXPECT_EQ(s.processor.correction, CorrectionForm::RootPolynomial2);
    EXPECT_EQ(s.processor.adaptation, Adaptation::Cat16);
    EXPECT_EQ(s.processor.exposure, 2.0);
    EXPECT_EQ(s.processor.display, "crt");
    EXPECT_EQ(s.processor.bits, 16);
    const ProcessorSpec defaults = read(base()).processor;
    EXPECT_EQ(defaults.whiteBalance, WhiteBalance::Illuminant);
    EXPECT_EQ(defaults.illuminant, "illuminants/D65");
    for (const auto& [text, expected] : std::vector<std::pair<const char*, const char*>>{
             {R"({"white_balance": "grey world"})", "processor.white_balance: 'grey world' is not one of"},
             {R"({"white_balance": "patch"})", "processor.patch: the patch white balance needs"},
             {R"({"patch": [0, 0, 4, 4]})", "processor.patch: a patch is for \"white_balance\": \"patch\""},
             {R"({"white_balance": "patch", "patch": [0, 0, 4.5, 4]})", "processor.patch.2: expected a whole number"},
             {R"({"illuminant": "illuminants/D66"})", "processor.illuminant"},
             {R"({"demosaic": "ahd"})", "processor.demosaic: 'ahd' is not one of bilinear, malvar2004"},
             {R"({"colour_correction": "cubic"})", "processor.colour_correction"},
             {R"({"adaptation": "brad"})", "processor.adaptation"},
             {R"({"exposure": 0})", "processor.exposure"},
             {R"({"gamma": 2.2})", "processor.gamma: unknown key for the processor"},
             {R"({"display": "lcd"})", "processor.display: 'lcd' is not one of srgb, crt"},
             {R"({"bits": 12})", "processor.bits: expected 8 or 16 bits per channel, got 12"},
         }) {
        const std::string e = error(processor(text));
        EXPECT_NE(e.find(expected), std::string::npos) << text << " → " << e;
    }
}

TEST_F(SensorFile, ALensIsReadWithItsKeysChecked) {
    auto j = base();
    j["optics"]["lens"] = nlohmann::ordered_json::parse(
        R"({"defocus_um": -12, "longitudinal_ca_um": {"wavelengths_nm": [450, 650], "values": [-20, 15]},
            "lateral_ca": 0.001, "olpf_um": 2.5, "pixel_aperture": false})");
    const SensorSpec s = read(j);
    ASSERT_TRUE(s.lens.has_value());
    EXPECT_TRUE(s.lens->diffraction);
    EXPECT_FALSE(s.lens->pixelAperture);
    EXPECT_EQ(s.lens->defocus_um, -12.0);
    EXPECT_EQ(s.lens->olpf_um, 2.5);
    EXPECT_EQ(s.lens->focusShift_um->values, (std::vector<double>{-20, 15}));
    EXPECT_TRUE(s.lens->lateralCa->isConstant());
    EXPECT_FALSE(read(base()).lens.has_value());  // no lens: nothing runs
    j["optics"]["lens"] = nlohmann::ordered_json::parse(R"({"defocus": 3})");
    EXPECT_NE(error(j).find("optics.lens.defocus: "), std::string::npos) << error(j);
    j["optics"]["lens"] = nlohmann::ordered_json::parse(R"({"lateral_ca": 0.5})");
    EXPECT_NE(error(j).find("optics.lens.lateral_ca: "), std::string::npos) << error(j);
    j["optics"]["lens"] = nlohmann::ordered_json::parse(R"({"zernike_waves": {"4": 0.05, "11": {"wavelengths_nm": [400, 700], "values": [0.1, -0.1]}}})");
    const SensorSpec z = read(j);
    ASSERT_EQ(z.lens->zernike.size(), 11u);
    EXPECT_EQ(*z.lens->zernike[3].constant, 0.05);
    EXPECT_EQ(*z.lens->zernike[0].constant, 0.0);
    EXPECT_EQ(z.lens->zernike[10].values, (std::vector<double>{0.1, -0.1}));
    j["optics"]["lens"] = nlohmann::ordered_json::parse(R"({"zernike_waves": {"0": 0.05}})");
    EXPECT_NE(error(j).find("optics.lens.zernike_waves.0: expected Noll's index"), std::string::npos) << error(j);
    j["optics"]["lens"] = nlohmann::ordered_json::parse(R"({"diffraction": "yes"})");
    EXPECT_NE(error(j).find("optics.lens.diffraction: expected true or false"), std::string::npos) << error(j);
}
