// Transparent materials (scene/material_reader_transparent.cpp): thin sheets, media, dyes, slabs.
#include "scene/scene_json_test_util.h"

#include "scene/scene_on_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace metamer;
using namespace metamer::test;

TEST(SceneJson, TransparentMaterialsAndBoxes) {
    Json d = baseScene();
    d["materials"]["gel"] = parse(R"({"transmittance": {"wavelengths_nm": [400, 700], "values": [0.2, 0.9]}})");
    d["materials"]["dye"] =
        parse(R"({"absorbance": 1.5, "dyes": [{"absorptivity": 200, "concentration": 0.01},
                                              {"absorptivity": 50, "concentration": 0.1}]})");
    d["objects"][4]["material"] = "gel";
    d["objects"][3] = parse(R"({"shape": "box", "center": [3, 0, 0], "size": [0.5, 1, 2], "material": "dye"})");
    d["objects"].push_back(parse(R"({"shape": "sphere", "center": [-3, 0, 0], "radius": 0.5, "material": "white"})"));
    const Scene s = load(d);
    const Mesh& box = s.meshes[3];
    EXPECT_TRUE(box.closed);
    EXPECT_EQ(box.indices.size(), 36u);
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    for (const glm::dvec3& p : box.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    EXPECT_EQ(lo, glm::dvec3(2.75, -0.5, -1));
    EXPECT_EQ(hi, glm::dvec3(3.25, 0.5, 1));
    const SceneOnGrid g = resampleScene(s, s.grid);
    const size_t gel = size_t(std::find_if(s.materials.begin(), s.materials.end(), [](const Material& m) { return m.name == "gel"; }) -
                              s.materials.begin());
    const size_t dye = size_t(std::find_if(s.materials.begin(), s.materials.end(), [](const Material& m) { return m.name == "dye"; }) -
                              s.materials.begin());
    EXPECT_TRUE(s.materials[gel].isFilter());
    EXPECT_TRUE(s.materials[dye].isMedium());
    EXPECT_TRUE(s.hasTransparency());
    // 400 nm and 700 nm (bands 2 and 32 of 380:780:10), the data's ends; 0 outside them, as for a reflectance.
    EXPECT_DOUBLE_EQ(g.materials[gel].transmittance[2], 0.2);
    EXPECT_DOUBLE_EQ(g.materials[gel].transmittance[32], 0.9);
    EXPECT_EQ(g.materials[gel].transmittance[0], 0.0);
    // a = 1.5 m⁻¹ + 100 cm/m × (200 × 0.01 + 50 × 0.1) per cm = 701.5 m⁻¹, at every band.
    ASSERT_EQ(g.materials[dye].absorbance.size(), size_t(g.grid.bands()));
    for (double a : g.materials[dye].absorbance) EXPECT_NEAR(a, 701.5, 1e-9);
    EXPECT_TRUE(g.materials[dye].diffuse.size() == size_t(g.grid.bands()) && g.materials[dye].diffuse[0] == 0.0);
}

TEST(SceneJson, SlabsAndTheirRefractiveIndices) {
    Json d = baseScene();
    d["materials"]["window"] = parse(R"({"slab": {"ior": "N-BK7", "thickness": 0.006, "absorbance": 12}})");
    d["materials"]["crown"] = parse(R"({"slab": {"ior": {"cauchy": {"A": 1.5046, "B": 0.0042}}, "thickness": 0.01}})");
    d["materials"]["flint"] =
        parse(R"({"slab": {"ior": {"sellmeier": {"B": [1.34533359, 0.209073176, 0.937357162],
                                                 "C": [0.00997743871, 0.0470450767, 111.886764]}}, "thickness": 0.01}})");
    d["materials"]["table"] = parse(R"({"slab": {"ior": {"wavelengths_nm": [400, 700], "values": [1.6, 1.5]}, "thickness": 0.002}})");
    d["objects"][4]["material"] = "window";
    d["objects"].push_back(parse(R"({"shape": "quad", "center": [0, 0, -4], "normal": [0, 0, 1], "size": [1, 1], "material": "crown"})"));
    d["objects"].push_back(parse(R"({"shape": "quad", "center": [0, 0, -5], "normal": [0, 0, 1], "size": [1, 1], "material": "flint"})"));
    d["objects"].push_back(parse(R"({"shape": "quad", "center": [0, 0, -6], "normal": [0, 0, 1], "size": [1, 1], "material": "table"})"));
    const Scene s = load(d);
    const SceneOnGrid g = resampleScene(s, s.grid);
    auto index = [&](const char* name) {
        return size_t(std::find_if(s.materials.begin(), s.materials.end(), [&](const Material& m) { return m.name == name; }) -
                      s.materials.begin());
    };
    const MaterialOnGrid &window = g.materials[index("window")], &crown = g.materials[index("crown")],
                         &flint = g.materials[index("flint")], &table = g.materials[index("table")];
    ASSERT_TRUE(window.isSlab() && crown.isSlab() && flint.isSlab() && table.isSlab());
    EXPECT_DOUBLE_EQ(window.slabThickness, 0.006);
    EXPECT_DOUBLE_EQ(window.slabAbsorbance[5], 12.0);
    EXPECT_EQ(crown.slabAbsorbance[5], 0.0);
    // Band 21 of 380:780:10 is 590 nm: N-BK7 ≈ 1.5168 near the d line; Cauchy A + B/λ²; the
    // table linear between its points; dispersion: n falls with wavelength.
    EXPECT_NEAR(window.ior[21], nbk7().at(590.0), 1e-15);
    EXPECT_NEAR(window.ior[21], 1.5168, 2e-4);
    EXPECT_NEAR(crown.ior[21], 1.5046 + 0.0042 / (0.59 * 0.59), 1e-12);
    EXPECT_NEAR(table.ior[2], 1.6, 1e-12);  // 400 nm
    EXPECT_NEAR(table.ior[17], 1.55, 1e-12);  // 550 nm
    EXPECT_GT(flint.ior[2], flint.ior[30]);
    EXPECT_TRUE(s.hasTransparency());
}

const BadCase kBadCases[] = {
    // Transparent materials (docs/scene-format.md, "Transparent materials").
    {"SlabWithoutThickness", [](Json& d) { d["materials"]["glass"] = parse(R"({"slab": {"ior": 1.5}})"); },
     "materials.glass.slab.thickness", "missing required key"},
    {"SlabIndexBelowOne", [](Json& d) { d["materials"]["glass"] = parse(R"({"slab": {"ior": 0.9, "thickness": 0.01}})"); },
     "materials.glass.slab.ior", "outside the allowed range"},
    {"SlabUnknownGlass", [](Json& d) { d["materials"]["glass"] = parse(R"({"slab": {"ior": "BK7", "thickness": 0.01}})"); },
     "materials.glass.slab.ior", "unknown glass 'BK7'; expected a number (1 … 5), \"N-BK7\""},
    {"SlabSellmeierMismatch",
     [](Json& d) { d["materials"]["glass"] = parse(R"({"slab": {"ior": {"sellmeier": {"B": [1, 0.2], "C": [0.006]}}, "thickness": 0.01}})"); },
     "materials.glass.slab.ior.sellmeier", "expected as many B as C coefficients"},
    {"SlabBesideTransmittance",
     [](Json& d) { d["materials"]["glass"] = parse(R"({"slab": {"ior": 1.5, "thickness": 0.01}, "transmittance": 0.5})"); },
     "materials.glass.transmittance", "not allowed beside 'slab'"},
    {"SlabWithDiffuse", [](Json& d) { d["materials"]["glass"] = parse(R"({"slab": {"ior": 1.5, "thickness": 0.01}, "diffuse": 0.1})"); },
     "materials.glass.diffuse", "not allowed in a transparent material (it has a 'slab')"},
    {"FilterWithDiffuse", [](Json& d) { d["materials"]["gel"] = parse(R"({"transmittance": 0.5, "diffuse": 0.2})"); },
     "materials.gel.diffuse", "not allowed in a transparent material (it has a 'transmittance')"},
    {"FilterAndMedium", [](Json& d) { d["materials"]["gel"] = parse(R"({"transmittance": 0.5, "absorbance": 2})"); },
     "materials.gel.absorbance", "a material is either a thin sheet"},
    {"TransmittanceAboveOne", [](Json& d) { d["materials"]["gel"] = parse(R"({"transmittance": 1.5})"); },
     "materials.gel.transmittance", "a transmittance must be within [0, 1], got 1.5"},
    {"NegativeAbsorbance", [](Json& d) { d["materials"]["dye"] = parse(R"({"absorbance": -1})"); },
     "materials.dye.absorbance", "an absorbance must be ≥ 0"},
    {"MediumWithGloss", [](Json& d) { d["materials"]["dye"] = parse(R"({"absorbance": 1, "gloss": 3})"); },
     "materials.dye.gloss", "not allowed in a transparent material (it has an 'absorbance' or 'dyes')"},
    {"DyesNotAList", [](Json& d) { d["materials"]["dye"] = parse(R"({"dyes": {"absorptivity": 1}})"); },
     "materials.dye.dyes", "expected a non-empty list"},
    {"DyeWithoutConcentration", [](Json& d) { d["materials"]["dye"] = parse(R"({"dyes": [{"absorptivity": 100}]})"); },
     "materials.dye.dyes.0.concentration", "missing required key"},
    {"DyeConcentrationTypo",
     [](Json& d) { d["materials"]["dye"] = parse(R"({"dyes": [{"absorptivity": 100, "concentraton": 1}]})"); },
     "materials.dye.dyes.0.concentraton", "did you mean 'concentration'?"},
    {"MediumOnAnOpenQuad",
     [](Json& d) {
         d["materials"]["dye"] = parse(R"({"absorbance": 2})");
         d["objects"][4]["material"] = "dye";
     },
     "objects.4.material", "is an absorbing medium, which must fill a closed mesh"},
};

INSTANTIATE_TEST_SUITE_P(All, SceneJsonBad, ::testing::ValuesIn(kBadCases), badCaseName);

// Which transparent scenes the response pass carries (Scene::transparencyInResponses; docs/color.md,
// "The response pass"): sheets and media over rank-one fluorescence, with one planar slab; not two
// slabs, a slab that is not planar, or more sheet and medium materials than one channel pass holds.
TEST(SceneJson, WhichTransparentScenesTheResponsePassCarries) {
    Json d = baseScene();
    d["materials"]["gel"] = parse(R"({"transmittance": 0.5})");
    d["materials"]["window"] = parse(R"({"slab": {"ior": "N-BK7", "thickness": 0.006}})");
    d["objects"][4]["material"] = "gel";
    EXPECT_TRUE(load(d).transparencyInResponses());
    EXPECT_FALSE(load(d).displayNeedsBands());
    const Json window = parse(R"({"shape": "quad", "center": [0, 0, -4], "normal": [0, 1, 1], "size": [1, 1], "material": "window"})");
    d["objects"].push_back(window);
    EXPECT_TRUE(load(d).transparencyInResponses());  // one planar slab
    Json two = d;
    two["objects"].push_back(window);
    two["objects"].back()["center"] = parse("[0, 0, -5]");
    EXPECT_FALSE(load(two).transparencyInResponses());  // their reflections add in depth order
    EXPECT_TRUE(load(two).displayNeedsBands());
    Json box = d;
    box["objects"].back() = parse(R"({"shape": "box", "center": [0, 0, -4], "size": [1, 1, 0.1], "material": "window"})");
    EXPECT_FALSE(load(box).transparencyInResponses());  // crossed twice, at two angles
    Json many = d;
    for (int i = 1; i < 16; ++i) many["materials"]["gel" + std::to_string(i)] = parse(R"({"transmittance": 0.5})");
    EXPECT_TRUE(load(many).transparencyInResponses());  // 16 beside a slab: one split channel pass
    many["materials"]["gel16"] = parse(R"({"transmittance": 0.5})");
    EXPECT_FALSE(load(many).transparencyInResponses());
}
