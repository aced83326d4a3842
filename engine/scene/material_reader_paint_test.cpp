// Paints' bad inputs (scene/material_reader_paint.cpp): layers, pigments, substrate, surface, maps.
#include "scene/scene_json_test_util.h"

#include <gtest/gtest.h>

using namespace metamer;
using namespace metamer::test;

const BadCase kBadCases[] = {
    // Paints (docs/scene-format.md, "Paints and coatings").
    {"PaintWithDiffuse", [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": [{"K": 1, "S": 9, "thickness": "opaque"}], "diffuse": 0.5})"); },
     "materials.paint.diffuse", "not allowed beside 'layers'"},
    {"PaintWithoutSubstrate", [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": [{"K": 1, "S": 9, "thickness": 1e-5}]})"); },
     "materials.paint.substrate", "missing required key (what lies beneath the layers"},
    {"OpaquePaintWithSubstrate",
     [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": [{"K": 1, "S": 9, "thickness": "opaque"}], "substrate": 0.8})"); },
     "materials.paint.substrate", "the bottom layer is opaque"},
    {"OpaqueUpperLayer",
     [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": [{"K": 1, "S": 9, "thickness": 1e-5}, {"K": 1, "S": 9, "thickness": "opaque"}], "substrate": 0.8})"); },
     "materials.paint.layers.1.thickness", "only the bottom layer may be opaque"},
    {"LayersNotAList", [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": {"K": 1}, "substrate": 0})"); },
     "materials.paint.layers", "expected a list of 1 … 64 layers, bottom first"},
    {"LayerWithoutAnything", [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": [{"thickness": 1e-5}], "substrate": 0})"); },
     "materials.paint.layers.0", "a layer needs 'pigments', or its own 'K' and 'S'"},
    {"LayerZeroThickness", [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": [{"K": 1, "thickness": 0}], "substrate": 0})"); },
     "materials.paint.layers.0.thickness", "outside the allowed range"},
    {"LayerThicknessWord", [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": [{"K": 1, "thickness": "thick"}], "substrate": 0})"); },
     "materials.paint.layers.0.thickness", "expected a thickness in metres or \"opaque\", got \"thick\""},
    {"NegativeScattering", [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": [{"K": 1, "S": -2, "thickness": 1e-5}], "substrate": 0})"); },
     "materials.paint.layers.0.S", "a Kubelka–Munk coefficient must be within [0, 1e12) per metre, got -2"},
    {"UnknownPigment",
     [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": [{"pigments": [{"pigment": "pigments/unobtainium", "concentration": 0.1}], "thickness": "opaque"}]})"); },
     "materials.paint.layers.0.pigments.0.pigment", "unknown pigment 'pigments/unobtainium'"},
    {"PigmentWithoutConcentration",
     [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": [{"pigments": [{"k": 1, "s": 2}], "thickness": "opaque"}]})"); },
     "materials.paint.layers.0.pigments.0.concentration", "missing required key"},
    {"PigmentNameAndSpectra",
     [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": [{"pigments": [{"pigment": "x", "k": 1, "concentration": 1}], "thickness": "opaque"}]})"); },
     "materials.paint.layers.0.pigments.0.k", "not allowed"},
    {"SubstrateUnknownMaterial",
     [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": [{"K": 1, "S": 9, "thickness": 1e-5}], "substrate": {"material": "primer"}})"); },
     "materials.paint.substrate.material", "unknown material 'primer': a substrate must be a material defined before this one"},
    {"SubstrateTransparentMaterial",
     [](Json& d) {
         d["materials"]["gel"] = parse(R"({"transmittance": 0.5})");
         d["materials"]["paint"] = parse(R"({"layers": [{"K": 1, "S": 9, "thickness": 1e-5}], "substrate": {"material": "gel"}})");
     },
     "materials.paint.substrate.material", "material 'gel' is transparent"},
    {"SurfaceBothForms",
     [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": [{"K": 1, "S": 9, "thickness": "opaque"}], "surface": {"ior": 1.5, "k1": 0.04}})"); },
     "materials.paint.surface.k1", "not allowed"},
    {"SurfaceK2OfOne",
     [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": [{"K": 1, "S": 9, "thickness": "opaque"}], "surface": {"k1": 0.04, "k2": 1}})"); },
     "materials.paint.surface.k2", "outside the allowed range"},
    {"SubstrateWithoutLayers", [](Json& d) { d["materials"]["white"]["substrate"] = 0.5; },
     "materials.white.substrate", "'substrate' belongs to a paint"},
    {"ThicknessMapOnASphere",
     [](Json& d) {
         d["materials"]["paint"] = parse(R"({"layers": [{"K": 1, "S": 9, "thickness": 1e-5, "thickness_map": "wedge.png"}], "substrate": 0.5})");
         d["objects"][3]["material"] = "paint";
     },
     "objects.3.material", "has textures but this object has no texture coordinates"},
    {"ThicknessMapOnAnOpaqueLayer",
     [](Json& d) { d["materials"]["paint"] = parse(R"({"layers": [{"K": 1, "S": 9, "thickness": "opaque", "thickness_map": "wedge.png"}]})"); },
     "materials.paint.layers.0.thickness_map", "an opaque layer has no thickness to vary"},
};

INSTANTIATE_TEST_SUITE_P(All, SceneJsonBad, ::testing::ValuesIn(kBadCases), badCaseName);
