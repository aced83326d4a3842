// libFuzzer target: the scene parser and --set overrides.
//
// Input layout: SCENE [\0 OVERRIDE [\0 OVERRIDE ...]]. SCENE is scene-file text given to
// loadSceneFromString as if it were <tmp>/fuzz.json; each OVERRIDE is one --set KEY=VALUE string.
// An empty SCENE (the input starts with \0) stands for scenes/spheres.json, so that overrides are
// fuzzed against a scene that loads. Library names resolve in the real spectra library; relative
// paths resolve in a private temporary folder holding copies of the test fixtures (local.csv,
// bad.csv, cube.gltf, cube.glb, strip.gltf, ..., the glTF files with embedded images) and of
// scenes/assets/ (meshes, buffers, textures), so the paths the seeds name exist. A scene that loads is then resampled onto its grid, as both renderers do next.
// Input errors (metamer::Error) are expected; anything else is a finding.
#include "fuzz_support.h"

#include "scene/scene_json.h"
#include "scene/scene_on_grid.h"
#include "spectral/library.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

struct Fixture {
    fs::path sceneFile;   // <tmp>/fuzz.json (never written: only its folder matters)
    SpectrumLibrary lib;  // the real library (METAMER_SPECTRA, else the source tree's spectra/)
    std::string baseScene;
};

std::string readText(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

Fixture& fixture() {
    static Fixture f = [] {
        const fs::path src = METAMER_SOURCE_DIR;
        const fs::path dir = fuzz::workDir();
        const auto copy = fs::copy_options::overwrite_existing | fs::copy_options::recursive;
        for (const char* fixtures : {"scene", "gltf"})
            for (const auto& e : fs::directory_iterator(src / "tests" / "data" / fixtures))
                if (e.is_regular_file() && e.path().extension() != ".py") fs::copy(e.path(), dir / e.path().filename(), copy);
        fs::create_directories(dir / "assets");
        for (const auto& e : fs::directory_iterator(src / "scenes" / "assets"))
            if (e.path().extension() != ".py") fs::copy(e.path(), dir / "assets" / e.path().filename(), copy);
        return Fixture{dir / "fuzz.json", SpectrumLibrary(), readText(src / "scenes" / "spheres.json")};
    }();
    return f;
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool unit(const glm::dvec3& v) { return finite(v) && std::fabs(glm::length(v) - 1.0) < 1e-6; }

// What scene/scene.h promises of a loaded scene: world-space geometry in finite numbers, unit
// normals and directions, indices in range, a camera with a defined view.
void checkScene(const Scene& s) {
    const Camera& c = s.camera;
    METAMER_FUZZ_CHECK(c.width >= 1 && c.height >= 1);
    METAMER_FUZZ_CHECK(finite(c.position) && finite(c.target) && unit(c.up));
    const glm::dvec3 view = c.target - c.position;
    METAMER_FUZZ_CHECK(finite(view) && glm::length(view) > 0.0);
    for (const Light& l : s.lights) {
        if (l.type == Light::Type::Directional) METAMER_FUZZ_CHECK(unit(l.direction));
        if (l.type == Light::Type::Point) METAMER_FUZZ_CHECK(finite(l.position));
        METAMER_FUZZ_CHECK(std::isfinite(l.scale) && l.scale >= 0);
    }
    for (const Mesh& m : s.meshes) {
        METAMER_FUZZ_CHECK(m.material < s.materials.size());
        METAMER_FUZZ_CHECK(m.normals.size() == m.positions.size());
        METAMER_FUZZ_CHECK(m.indices.size() % 3 == 0);
        for (uint32_t i : m.indices) METAMER_FUZZ_CHECK(i < m.positions.size());
        for (const glm::dvec3& p : m.positions) METAMER_FUZZ_CHECK(finite(p));
        for (const glm::dvec3& n : m.normals) METAMER_FUZZ_CHECK(unit(n));
    }
}

bool allFinite(const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

// Spectra with values near the top of the double range (beyond 1e300) may overflow band sums;
// the finiteness of everything else on the grid is checked.
bool tame(const SceneSpectrum& s) {
    if (s.spectrum.isConstant()) return true;
    return std::all_of(s.spectrum.values.begin(), s.spectrum.values.end(),
                       [](double x) { return std::fabs(x) < 1e300; });
}

void checkOnGrid(const Scene& scene, const SceneOnGrid& g) {
    const size_t bands = static_cast<size_t>(scene.grid.bands());
    for (const auto& e : g.lights) METAMER_FUZZ_CHECK(e.size() == bands && allFinite(e));
    for (size_t i = 0; i < g.materials.size(); ++i) {
        const Material& m = scene.materials[i];
        const MaterialOnGrid& mg = g.materials[i];
        METAMER_FUZZ_CHECK(mg.diffuse.size() == bands && mg.specular.size() == bands);
        if (tame(m.diffuse)) METAMER_FUZZ_CHECK(allFinite(mg.diffuse));
        if (tame(m.specular)) METAMER_FUZZ_CHECK(allFinite(mg.specular));
        if (m.fluorescence) {
            if (tame(m.fluorescence->excitation)) METAMER_FUZZ_CHECK(allFinite(mg.excitation));
            if (tame(m.fluorescence->emission)) METAMER_FUZZ_CHECK(allFinite(mg.emission));
        }
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::silenceWarnings();
    fixture();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    Fixture& f = fixture();
    const std::string input(reinterpret_cast<const char*>(data), size);
    size_t nul = input.find('\0');
    std::string text = input.substr(0, nul);
    std::vector<std::string> overrides;
    while (nul != std::string::npos) {
        size_t next = input.find('\0', nul + 1);
        overrides.push_back(input.substr(nul + 1, next == std::string::npos ? std::string::npos : next - nul - 1));
        nul = next;
    }
    if (text.empty() && !overrides.empty()) text = f.baseScene;

    try {
        Scene scene = loadSceneFromString(text, f.sceneFile, f.lib, overrides);
        checkScene(scene);
        SceneOnGrid onGrid = resampleScene(scene, scene.grid);
        METAMER_FUZZ_CHECK(onGrid.lights.size() == scene.lights.size());
        METAMER_FUZZ_CHECK(onGrid.materials.size() == scene.materials.size());
        checkOnGrid(scene, onGrid);
    } catch (const Error&) {
    }
    return 0;
}
