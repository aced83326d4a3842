// Opaque materials' bad inputs (scene/material_reader_opaque.cpp): diffuse, gloss, fluorescence.
#include "scene/scene_json_test_util.h"

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
};

INSTANTIATE_TEST_SUITE_P(All, SceneJsonBad, ::testing::ValuesIn(kBadCases), badCaseName);
