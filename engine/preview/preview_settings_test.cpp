// The pieces of the preview that need no window: --set/--split bookkeeping, the grid-step
// choices, pixel arguments and the file watch.
#include "preview/file_watch.h"
#include "preview/preview.h"
#include "preview/settings_panel.h"
#include "scene/scene_json.h"
#include "scene/scene_on_grid.h"

#include <gtest/gtest.h>

#include <fstream>
#include <unistd.h>

using namespace metamer;
using namespace metamer::preview;
namespace fs = std::filesystem;

TEST(PreviewSettings, AnEditedOverrideReplacesTheEarlierOneAndComesLast) {
    std::vector<std::string> o = {"lights.0.scale=2", "camera.width=64"};
    setOverride(o, "lights.0.scale", "3");
    EXPECT_EQ(o, (std::vector<std::string>{"camera.width=64", "lights.0.scale=3"}));
    setOverride(o, "lights.0.spectrum", "illuminants/A");
    EXPECT_EQ(o.back(), "lights.0.spectrum=illuminants/A");
    EXPECT_EQ(o.size(), 3u);
    setOverride(o, "lights.0", "{}");  // a prefix of other keys is its own key
    EXPECT_EQ(o.size(), 4u);
}

TEST(PreviewSettings, GridStepKeepsTheStartAndTheLastWholeBand) {
    Grid g{380, 780, 5};
    EXPECT_EQ(gridWithStep(g, 20), (Grid{380, 780, 20}));
    EXPECT_EQ(gridWithStep(g, 50), (Grid{380, 780, 50}));
    Grid three = gridWithStep(g, 3);  // 400 nm is not a whole number of 3 nm steps
    EXPECT_EQ(three.end_nm, 779.0);
    EXPECT_NO_THROW(three.validate(Where{}));
    EXPECT_EQ(gridWithStep(Grid{300, 740, 5}, 0.5).bands(), 881);
}

TEST(PreviewSettings, SplitSettingsSetDisplayFieldsOrSceneOverrides) {
    RenderJob left;
    left.overrides = {"lights.0.spectrum=illuminants/D65"};
    RenderJob right = splitJob(left, {"lights.0.spectrum=illuminants/A", "detector=cie1964", "adapt=cat16",
                                      "display=crt", "mode=rgb", "grid=400:700:10"});
    EXPECT_EQ(right.overrides, (std::vector<std::string>{"lights.0.spectrum=illuminants/A"}));
    EXPECT_EQ(*right.detector, "cie1964");
    EXPECT_EQ(*right.adaptation, "cat16");
    EXPECT_EQ(*right.display, "crt");
    EXPECT_EQ(right.mode, "rgb");
    EXPECT_EQ(*right.grid, (Grid{400, 700, 10}));
    try {
        splitJob(left, {"no-equals-sign"});
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_EQ(e.where().key, "--split");
    }
}

TEST(PreviewSettings, PixelArguments) {
    EXPECT_EQ(parsePixel("12,34", "--probe"), glm::ivec2(12, 34));
    for (const char* bad : {"12", "12,", "a,b", "-1,3", "1,2,3", "1,2x"}) {
        try {
            parsePixel(bad, "--pin");
            ADD_FAILURE() << bad;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadInput);
            EXPECT_EQ(e.where().key, "--pin");
        }
    }
}

TEST(PreviewSettings, FileWatchSeesAChangeOnceAndAReplacedFile) {
    fs::path dir = fs::temp_directory_path() / ("metamer_watch_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    fs::path f = dir / "scene.json";
    std::ofstream(f) << "{}";
    FileWatch w(f, 0.0);
    EXPECT_FALSE(w.changed());
    std::ofstream(f) << "{\"a\": 1}";  // a different size
    EXPECT_TRUE(w.changed());
    EXPECT_FALSE(w.changed());
    // Replaced by rename, as editors save: a new time (set explicitly; file times are coarse).
    fs::path tmp = dir / "scene.json.tmp";
    std::ofstream(tmp) << "{\"a\": 2}";
    fs::last_write_time(tmp, fs::last_write_time(f) + std::chrono::seconds(2));
    fs::rename(tmp, f);
    EXPECT_TRUE(w.changed());
    fs::remove(f);  // missing for a moment: no change reported yet
    EXPECT_FALSE(w.changed());
    fs::remove_all(dir);
}

// The paint controls edit scene keys that load: a layer's thickness and a pigment's concentration.
TEST(PreviewSettings, PaintControlsSetKeysThatLoad) {
    const fs::path scene = fs::path(METAMER_SOURCE_DIR) / "scenes" / "paints.json";
    const SpectrumLibrary library;
    const Scene s = loadScene(scene, library);
    auto named = [](const Scene& sc, const std::string& n) {
        return *std::find_if(sc.materials.begin(), sc.materials.end(), [&](const Material& m) { return m.name == n; });
    };
    std::vector<std::string> o;
    setOverride(o, layerThicknessKey(named(s, "drawdown_over_black"), 0), "7.5e-05");
    setOverride(o, pigmentConcentrationKey(named(s, "mix_050"), 0, 2), "0.02");
    EXPECT_EQ(o, (std::vector<std::string>{"materials.drawdown_over_black.layers.0.thickness=7.5e-05",
                                           "materials.mix_050.layers.0.pigments.2.concentration=0.02"}));
    const Scene edited = loadScene(scene, library, o);
    EXPECT_DOUBLE_EQ(named(edited, "drawdown_over_black").paint->layers[0].thickness_m, 7.5e-5);
    EXPECT_DOUBLE_EQ(named(edited, "mix_050").paint->layers[0].pigments[2].concentration, 0.02);
    // And the reflectance follows: more blue, less light at 550 nm.
    const SceneOnGrid before = resampleScene(s, s.grid), after = resampleScene(edited, edited.grid);
    size_t mix = 0;
    while (s.materials[mix].name != "mix_050") ++mix;
    EXPECT_LT(after.materials[mix].diffuse[34], before.materials[mix].diffuse[34]);
}

// The transparent objects' controls edit scene keys that load: a filter swapped for another from
// the library, a dye's concentration doubled (its absorbance per metre doubles).
TEST(PreviewSettings, TransparentObjectControlsSetKeysThatLoad) {
    const fs::path scene = fs::path(METAMER_SOURCE_DIR) / "scenes" / "filters.json";
    const SpectrumLibrary library;
    Scene s = loadScene(scene, library);
    auto named = [](const Scene& sc, const std::string& n) {
        return *std::find_if(sc.materials.begin(), sc.materials.end(), [&](const Material& m) { return m.name == n; });
    };
    const Material gel = named(s, "amber_gel"), dye = named(s, "rhodamine");
    std::vector<std::string> o;
    setOverride(o, transmittanceKey(gel), "filters/green_gel");
    setOverride(o, dyeConcentrationKey(dye, 0), "1e-05");
    EXPECT_EQ(o, (std::vector<std::string>{"materials.amber_gel.transmittance=filters/green_gel",
                                           "materials.rhodamine.dyes.0.concentration=1e-05"}));
    const Scene edited = loadScene(scene, library, o);
    EXPECT_EQ(named(edited, "amber_gel").transmittance->spectrum.source, "filters/green_gel");
    EXPECT_DOUBLE_EQ(named(edited, "rhodamine").dyes[0].concentration, 1e-5);
    EXPECT_EQ(absorbanceKey(named(s, "tinted_glass")), "materials.tinted_glass.absorbance");
}

// The interreflection switch undoes its own override rather than piling them up, and what it sets
// loads: on a scene without the key, on then off leaves nothing; on a scene with it, off then on
// brings the file's settings back.
TEST(PreviewSettings, TheInterreflectionSwitchTogglesAndLoads) {
    const SpectrumLibrary library;
    std::vector<std::string> o;
    setInterreflection(o, true);
    EXPECT_EQ(o, (std::vector<std::string>{"interreflection=true"}));
    const fs::path plain = fs::path(METAMER_SOURCE_DIR) / "scenes" / "colorchecker.json";
    EXPECT_FALSE(loadScene(plain, library).interreflection.has_value());
    EXPECT_TRUE(loadScene(plain, library, o).interreflection.has_value());
    setInterreflection(o, false);
    EXPECT_TRUE(o.empty());

    const fs::path cornell = fs::path(METAMER_SOURCE_DIR) / "scenes" / "cornell-box.json";
    setInterreflection(o, false);
    EXPECT_EQ(o, (std::vector<std::string>{"interreflection=false"}));
    EXPECT_FALSE(loadScene(cornell, library, o).interreflection.has_value());
    setInterreflection(o, true);
    EXPECT_TRUE(o.empty());
    setOverride(o, "interreflection.element_size", "0.14");
    const Scene coarser = loadScene(cornell, library, o);
    ASSERT_TRUE(coarser.interreflection.has_value());
    EXPECT_DOUBLE_EQ(*coarser.interreflection->elementSize_m, 0.14);
    EXPECT_DOUBLE_EQ(coarser.interreflection->tolerance, 1e-5);  // the file's other settings stay
}
