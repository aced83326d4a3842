// Opaque materials' bad inputs (scene/material_reader_opaque.cpp): diffuse, gloss, fluorescence,
// emitted radiance.
#include "scene/scene_json_test_util.h"
#include "support/capture_warnings.h"

#include <gtest/gtest.h>

using namespace metamer;
using namespace metamer::test;

const BadCase kBadCases[] = {
    {"ReflectanceAboveOne", [](Json& d) { d["materials"]["white"]["diffuse"] = 1.5; }, "materials.white.diffuse",
     "within [0, 1]"},
    {"MaterialKeyTypo", [](Json& d) { d["materials"]["white"]["difuse"] = 0.5; }, "materials.white.difuse",
     "unknown key; did you mean 'diffuse'?"},
    {"MaterialDiffuseMissing", [](Json& d) { d["materials"]["white"] = parse(R"({"specular": 0.1, "gloss": 5})"); },
     "materials.white.diffuse", "missing required key"},
    {"GlossMissingWithSpecular", [](Json& d) { d["materials"]["skin"].erase("gloss"); }, "materials.skin.gloss",
     "missing required key"},
    {"GlossNegative", [](Json& d) { d["materials"]["skin"]["gloss"] = -1; }, "materials.skin.gloss",
     "outside the allowed range [0, 1e+06]"},
    {"GlossHuge", [](Json& d) { d["materials"]["skin"]["gloss"] = 2e6; }, "materials.skin.gloss", "outside the allowed range"},
    {"QuantumYieldAboveOne", [](Json& d) { d["materials"]["brightener"]["fluorescence"]["quantum_yield"] = 1.2; },
     "materials.brightener.fluorescence.quantum_yield", "outside the allowed range [0, 1]"},
    {"QuantumYieldMissing", [](Json& d) { d["materials"]["brightener"]["fluorescence"].erase("quantum_yield"); },
     "materials.brightener.fluorescence.quantum_yield", "missing required key"},
    {"EmissionMissing", [](Json& d) { d["materials"]["brightener"]["fluorescence"].erase("emission"); },
     "materials.brightener.fluorescence.emission", "missing required key"},
    {"EmissionConstant", [](Json& d) { d["materials"]["brightener"]["fluorescence"]["emission"] = 1; },
     "materials.brightener.fluorescence.emission", "must be sampled data"},
    {"ExcitationUnknown", [](Json& d) { d["materials"]["brightener"]["fluorescence"]["excitation"] = "fluorescent/brightener_x"; },
     "materials.brightener.fluorescence.excitation", "did you mean 'fluorescent/brightener_ex'?"},
    {"EmittedRadianceNotAnObject", [](Json& d) { d["materials"]["white"]["emitted_radiance"] = "illuminants/D65"; },
     "materials.white.emitted_radiance", "expected an object"},
    {"EmittedRadianceSpectrumMissing", [](Json& d) { d["materials"]["white"]["emitted_radiance"] = parse(R"({"scale": 2})"); },
     "materials.white.emitted_radiance.spectrum", "missing required key"},
    {"EmittedRadianceNegativeScale",
     [](Json& d) { d["materials"]["white"]["emitted_radiance"] = parse(R"({"spectrum": "illuminants/D65", "scale": -1})"); },
     "materials.white.emitted_radiance.scale", "must be ≥ 0, got -1"},
    {"EmittedRadianceKeyTypo",
     [](Json& d) { d["materials"]["white"]["emitted_radiance"] = parse(R"({"spectrum": "illuminants/D65", "scal": 1})"); },
     "materials.white.emitted_radiance.scal", "did you mean 'scale'?"},
};

INSTANTIATE_TEST_SUITE_P(All, SceneJsonBad, ::testing::ValuesIn(kBadCases), badCaseName);

// An emitter is read as a light's spectrum × scale; without interreflection it lights nothing else,
// which the scene says when it is read (and with the key, it does not).
TEST(OpaqueMaterial, EmittedRadianceIsReadAndWarnedAboutWithoutInterreflection) {
    Json doc = baseScene();
    doc["materials"]["white"]["emitted_radiance"] = parse(R"({"spectrum": "illuminants/D65", "scale": 0.25})");
    {
        CaptureWarnings warnings;
        const Scene s = load(doc);
        ASSERT_TRUE(s.materials[1].emitter.has_value());
        EXPECT_EQ(s.materials[1].emitter->scale, 0.25);
        EXPECT_EQ(s.materials[1].emitter->spectrum.spectrum.source, "illuminants/D65");
        EXPECT_TRUE(s.hasEmitters());
        EXPECT_TRUE(s.displayNeedsBands());
        ASSERT_EQ(warnings.lines().size(), 1u);
        EXPECT_NE(warnings.lines()[0].find("materials.white.emitted_radiance"), std::string::npos) << warnings.lines()[0];
        EXPECT_NE(warnings.lines()[0].find("lights nothing else"), std::string::npos) << warnings.lines()[0];
    }
    doc["interreflection"] = true;
    CaptureWarnings warnings;
    load(doc);
    EXPECT_TRUE(warnings.lines().empty());
}
