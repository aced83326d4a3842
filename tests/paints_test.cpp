// Paints and coatings by Kubelka–Munk (docs/physics.md, "Paints and coatings"): scenes read from
// JSON, rendered by the GPU path and by the CPU reference, against known answers. A paint under an
// ambient irradiance E = π (constant over λ) has radiance L = ρ·E/π = ρ, its body reflectance, so
// each pixel is the Kubelka–Munk value itself. The known answers are the issue's, computed by the
// numpy and scipy oracles of tests/python/check_kubelka_munk.py; where a test needs other values
// it computes them with Kubelka's textbook closed form (not the engine's form).
#include "io/image_file.h"
#include "reference/cpu_renderer.h"
#include "render/spectral_pass.h"
#include "scene/scene_json.h"
#include "spectral/library.h"
#include "support/capture_warnings.h"
#include "support/gpu.h"
#include "support/scene_builders.h"
#include "support/temp_folder.h"

#include <fmt/format.h>

#include <cmath>
#include <string>
#include <vector>

using namespace metamer;
using namespace metamer::test;

namespace {

// Kubelka's closed form over a substrate Rg, a = 1 + K/S, b = √(a² − 1).
double textbook(double K, double S, double X, double Rg) {
    const double a = 1.0 + K / S, b = std::sqrt(a * a - 1.0), coth = 1.0 / std::tanh(b * S * X);
    return (1.0 - Rg * (a - b * coth)) / (a - Rg + b * coth);
}
double textbookInfinite(double kOverS) { return 1.0 + kOverS - std::sqrt(kOverS * kOverS + 2.0 * kOverS); }

// A row of `materials.size()` quads, 0.1 m apart along x, each seen by one pixel of an
// orthographic camera, under an ambient light of irradiance π: pixel i's radiance is material
// i's reflectance. `materials` is the JSON of the "materials" object's entries, in order.
std::string rowOfPatches(const std::vector<std::pair<std::string, std::string>>& materials,
                         const std::string& grid = R"({"start_nm": 400, "end_nm": 700, "step_nm": 10})") {
    std::string m, o;
    const size_t n = materials.size();
    for (size_t i = 0; i < n; ++i) {
        m += fmt::format("{}\"{}\": {}", i ? ", " : "", materials[i].first, materials[i].second);
        o += fmt::format(R"({}{{"shape": "quad", "center": [{}, 0, 0], "normal": [0, 0, 1], "size": [0.1, 0.1], "material": "{}"}})",
                         i ? ", " : "", (double(i) + 0.5) * 0.1, materials[i].first);
    }
    return fmt::format(R"({{
      "grid": {},
      "camera": {{"projection": "orthographic", "position": [{}, 0, 1], "target": [{}, 0, 0], "up": [0, 1, 0],
                  "height_m": 0.1, "width": {}, "height": 1}},
      "lights": [{{"type": "ambient", "spectrum": 1, "scale": 3.141592653589793}}],
      "materials": {{{}}},
      "objects": [{}]
    }})",
                       grid, n * 0.05, n * 0.05, n, m, o);
}

Scene load(const std::string& json, const std::filesystem::path& file = "paints-test.json") {
    static const SpectrumLibrary lib;
    return loadSceneFromString(json, file, lib);
}

struct Renders {
    SceneOnGrid grid;
    SpectralCube gpu;
    std::vector<std::vector<double>> cpu;  // [pixel x][band], the reference in double (row 0)
};
Renders renderBoth(const Scene& s) {
    Renders r{resampleScene(s, s.grid), {}, {}};
    const uint32_t before = gpu().validationErrors();
    SpectralPass pass(gpu(), s, r.grid);
    r.gpu = pass.render();
    EXPECT_NO_VALIDATION_ERRORS(before);
    ReferenceRenderer ref(s, r.grid);
    for (int x = 0; x < s.camera.width; ++x) {
        r.cpu.emplace_back(size_t(ref.bands()));
        ref.pixel(x, 0, r.cpu.back().data());
    }
    return r;
}

// Both renderers' pixel x in every band against `expected`: the CPU to 1e-6, the GPU to 1e-5.
void expectPatch(const Renders& r, int x, double expected, const char* what) {
    for (int b = 0; b < r.gpu.bands(); ++b) {
        EXPECT_NEAR(r.cpu[size_t(x)][size_t(b)], expected, 1e-6) << what << ": cpu, band " << b;
        EXPECT_NEAR(r.gpu.at(x, 0, b), expected, 1e-5) << what << ": gpu, band " << b;
    }
}

}  // namespace

TEST(Paints, TheIssuesKnownAnswersOnBothRenderers) {
    const Renders r = renderBoth(load(rowOfPatches({
        {"opaque", R"({"layers": [{"K": 0.1, "S": 1, "thickness": "opaque"}]})"},
        {"over_black", R"({"layers": [{"K": 1, "S": 10, "thickness": 0.1}], "substrate": 0})"},
        {"over_white", R"({"layers": [{"K": 1, "S": 10, "thickness": 0.1}], "substrate": 0.8})"},
        {"saunderson", R"({"layers": [{"K": 0.1, "S": 1, "thickness": "opaque"}], "surface": {"k1": 0.04, "k2": 0.6}})"},
        {"thin", R"({"layers": [{"K": 1, "S": 10, "thickness": 1e-9}], "substrate": 0.3})"},
        {"thick", R"({"layers": [{"K": 0.1, "S": 1, "thickness": 1000}], "substrate": 0.3})"},
    })));
    expectPatch(r, 0, 0.6417424, "K/S = 0.1: R∞");
    expectPatch(r, 1, 0.4610336, "K 1, S 10, X 0.1 over black");
    expectPatch(r, 2, 0.7123473, "over Rg = 0.8");
    // The body reflectance: Saunderson's 0.4407273 less the surface's own k1 = 0.04 (the specular term).
    expectPatch(r, 3, 0.4407273 - 0.04, "Saunderson, k1 0.04, k2 0.6");
    expectPatch(r, 4, 0.3, "X → 0: the substrate");
    expectPatch(r, 5, 0.6417424, "X → ∞: R∞");
}

TEST(Paints, TwoPigmentsMixedAtCAndOneMinusCFollowTheTwoConstantRule) {
    // Pigment A: k 2, s 40 (a white); B: k 30, s 3 (a dark). K = c·kA + (1 − c)·kB, S likewise.
    std::vector<std::pair<std::string, std::string>> row;
    for (int i = 0; i <= 10; ++i)
        row.emplace_back(fmt::format("mix{}", i),
                         fmt::format(R"({{"layers": [{{"pigments": [{{"k": 2, "s": 40, "concentration": {}}},
                                                                   {{"k": 30, "s": 3, "concentration": {}}}],
                                                      "thickness": "opaque"}}]}})",
                                     i / 10.0, 1.0 - i / 10.0));
    const Renders r = renderBoth(load(rowOfPatches(row)));
    for (int i = 0; i <= 10; ++i) {
        const double c = i / 10.0, K = c * 2 + (1 - c) * 30, S = c * 40 + (1 - c) * 3;
        expectPatch(r, i, textbookInfinite(K / S), "mixing row");
    }
}

TEST(Paints, SpectralPigmentsLayersAndSubstratesMatchTheClosedFormBandByBand) {
    // A yellow: absorbs below ~500 nm (K a logistic step), scatters more in the blue (S ∝ λ⁻¹), 20 µm
    // over a primer material; the primer is a 30 µm grey coat over a spectral card.
    std::string k = R"({"wavelengths_nm": [400, 450, 500, 550, 600, 700], "values": [9e4, 8e4, 3e4, 2e3, 5e2, 4e2]})";
    std::string s = R"({"wavelengths_nm": [400, 700], "values": [3e5, 1.7e5]})";
    std::string card = R"({"wavelengths_nm": [400, 700], "values": [0.2, 0.7]})";
    const Scene scene = load(rowOfPatches({
        {"primer", R"({"layers": [{"K": 2e4, "S": 1e5, "thickness": 3e-5}], "substrate": )" + card + "}"},
        {"yellow", R"({"layers": [{"pigments": [{"k": )" + k + R"(, "s": )" + s +
                       R"(, "concentration": 1}], "thickness": 2e-5}], "substrate": {"material": "primer"}})"},
    }));
    const Renders r = renderBoth(scene);
    const std::vector<double>& nm = r.grid.wavelengths_nm;
    auto lerp = [](double x, double x0, double x1, double y0, double y1) { return y0 + (y1 - y0) * (x - x0) / (x1 - x0); };
    for (size_t b = 0; b < nm.size(); ++b) {
        // The card is linear in λ, so its band averages are its values at the band centres.
        const double primer = textbook(2e4, 1e5, 3e-5, lerp(nm[b], 400, 700, 0.2, 0.7));
        EXPECT_NEAR(r.cpu[0][b], primer, 1e-6) << nm[b];
        EXPECT_NEAR(r.gpu.at(0, 0, int(b)), primer, 1e-5) << nm[b];
    }
    // The yellow over the primer: the grid (10 nm) is finer than the pigment's data, so its bands
    // take the linear interpolant at their centres (docs/physics.md, "Resampling").
    const std::vector<double> kNm{400, 450, 500, 550, 600, 700}, kValues{9e4, 8e4, 3e4, 2e3, 5e2, 4e2};
    for (size_t b = 0; b < nm.size(); ++b) {
        size_t i = 0;
        while (i + 2 < kNm.size() && nm[b] > kNm[i + 1]) ++i;
        const double K = lerp(nm[b], kNm[i], kNm[i + 1], kValues[i], kValues[i + 1]);
        const double S = lerp(nm[b], 400, 700, 3e5, 1.7e5);
        const double primer = textbook(2e4, 1e5, 3e-5, lerp(nm[b], 400, 700, 0.2, 0.7));
        EXPECT_NEAR(r.cpu[1][b], textbook(K, S, 2e-5, primer), 1e-6) << nm[b];
        EXPECT_NEAR(r.gpu.at(1, 0, int(b)), textbook(K, S, 2e-5, primer), 1e-5) << nm[b];
    }
}

TEST(Paints, SaundersonFromTheRefractiveIndexIntegratesFresnel) {
    const Renders r = renderBoth(load(rowOfPatches({
        {"n15", R"({"layers": [{"K": 0.1, "S": 1, "thickness": "opaque"}], "surface": {"ior": 1.5}})"},
    })));
    // k1 = 0.04; k2 = 0.59635 (the internal diffuse reflectance at n = 1.5, to 5 digits).
    const double rInf = 0.6417424, body = 0.96 * (1 - 0.59635) * rInf / (1 - 0.59635 * rInf);
    for (int b = 0; b < r.gpu.bands(); ++b) {
        EXPECT_NEAR(r.cpu[0][size_t(b)], body, 2e-5);
        EXPECT_NEAR(r.gpu.at(0, 0, b), body, 2e-5);
    }
}

TEST(Paints, AFluorescentPaintKeepsItsFluorescenceOverItsBodyReflectance) {
    // The same fluorescence over a paint and over a plain material whose diffuse is the paint's
    // body reflectance: the same radiance.
    const std::string fl = R"("fluorescence": {"excitation": {"wavelengths_nm": [400, 500, 550], "values": [0.3, 0.2, 0]},
                                                 "emission": {"wavelengths_nm": [520, 580, 640], "values": [0, 1, 0]},
                                                 "quantum_yield": 0.8})";
    const Renders paint = renderBoth(load(rowOfPatches({{"paint", R"({"layers": [{"K": 1, "S": 10, "thickness": 0.1}],
        "substrate": 0.2, )" + fl + "}"}})));
    const double body = textbook(1, 10, 0.1, 0.2);
    const Renders plain = renderBoth(load(rowOfPatches({{"plain", fmt::format(R"({{"diffuse": {:.17g}, {}}})", body, fl)}})));
    bool fluoresces = false;
    for (int b = 0; b < paint.gpu.bands(); ++b) {
        EXPECT_NEAR(paint.cpu[0][size_t(b)], plain.cpu[0][size_t(b)], 1e-12) << b;
        EXPECT_NEAR(paint.gpu.at(0, 0, b), plain.gpu.at(0, 0, b), 1e-6) << b;
        fluoresces |= paint.cpu[0][size_t(b)] > body + 1e-3;
    }
    EXPECT_TRUE(fluoresces);
}

class PaintMaps : public TempFolderTest {};

TEST_F(PaintMaps, AThicknessWedgeGivesEachTexelItsOwnKubelkaMunkReflectance) {
    // An 8 × 1 float map 0, 1/7 … 1 scales a 40 µm layer; pixel x sees texel x's centre.
    std::vector<float> wedge;
    for (int i = 0; i < 8; ++i) wedge.push_back(float(i) / 7.0f);
    writeImage(dir / "wedge.exr", ImageFile{8, 1, {"Y"}, {}}, wedge);
    const std::string json = R"({
      "grid": {"start_nm": 400, "end_nm": 700, "step_nm": 50},
      "camera": {"projection": "orthographic", "position": [0, 0, 1], "target": [0, 0, 0], "up": [0, 1, 0],
                 "height_m": 0.125, "width": 8, "height": 1},
      "lights": [{"type": "ambient", "spectrum": 1, "scale": 3.141592653589793}],
      "materials": {"drawdown": {"layers": [{"K": 2e4, "S": 2e5, "thickness": 4e-5, "thickness_map": "wedge.exr"}],
                                 "substrate": 0.05}},
      "objects": [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [1, 0.125], "material": "drawdown"}]
    })";
    const Scene s = load(json, dir / "wedge.json");
    const Renders r = renderBoth(s);
    for (int x = 0; x < 8; ++x) {
        const double X = 4e-5 * double(wedge[size_t(x)]), expected = X == 0 ? 0.05 : textbook(2e4, 2e5, X, 0.05);
        for (int b = 0; b < r.gpu.bands(); ++b) {
            EXPECT_NEAR(r.cpu[size_t(x)][size_t(b)], expected, 1e-6) << "texel " << x;
            EXPECT_NEAR(r.gpu.at(x, 0, b), expected, 1e-5) << "texel " << x;
        }
    }
    // The hiding test's contrast ratio grows with thickness towards 1.
    EXPECT_LT(r.cpu[1][0], r.cpu[7][0]);
}
