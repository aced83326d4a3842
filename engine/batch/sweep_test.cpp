// Sweep files and manifests (batch/sweep): the jobs they expand to, in order, and the errors a
// user gets for each mistake — naming the file, the key or the line, and what was expected.
#include "batch/sweep.h"
#include "batch/sweep_draws.h"

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <unistd.h>

using namespace metamer;
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

fs::path scratch() {
    const fs::path d = fs::temp_directory_path() / fmt::format("metamer-sweep-test-{}", ::getpid());
    fs::create_directories(d);
    return d;
}

fs::path write(const std::string& name, const std::string& text) {
    const fs::path p = scratch() / name;
    std::ofstream(p) << text;
    return p;
}

std::string errorOf(const std::string& name, const std::string& text) {
    try {
        readSweep(write(name, text));
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput) << e.what();
        return e.what();
    }
    return "(no error)";
}

const char* kSweep = R"({
  "scenes": ["a.json", "b.json"],
  "set": {"camera.width": 32},
  "render": {"write": "png,xyz", "detector": "cie1931"},
  "rows": [{"scene": "c.json", "set": ["lights.0.scale=2"], "render": {"mode": "rgb"}}],
  "axes": [
    {"name": "light", "set": "lights.0.spectrum", "values": ["illuminants/D65", "illuminants/A"]},
    {"render": "detector", "values": ["cie1931", "cie1964", "camera:nikon_d5100"]}
  ],
  "out": "dataset"
})";

}  // namespace

TEST(Sweep, ScenesAndRowsCrossedWithTheAxesLastAxisFastest) {
    const fs::path file = write("sweep.json", kSweep);
    const Sweep s = readSweep(file);
    ASSERT_EQ(s.size(), 3u * 2 * 3);
    EXPECT_EQ(s.out, fs::absolute(file).parent_path() / "dataset");
    const SweepJob first = s.job(0);
    EXPECT_EQ(first.scene, "a.json");
    EXPECT_EQ(first.overrides, (std::vector<std::string>{"camera.width=32", "lights.0.spectrum=illuminants/D65"}));
    EXPECT_EQ(first.render["detector"], "cie1931");
    EXPECT_EQ(first.render["write"], Json::array({"png", "xyz"}));
    EXPECT_EQ(first.origin, "scenes.0 × light=illuminants/D65, detector=cie1931");
    EXPECT_EQ(s.job(1).render["detector"], "cie1964");  // the last axis varies fastest
    EXPECT_EQ(s.job(3).overrides.back(), "lights.0.spectrum=illuminants/A");
    // A row: the common overrides first, then its own, then the axes'; its render settings over
    // the common ones, the axes' over both.
    const SweepJob row = s.job(12);
    EXPECT_EQ(row.scene, "c.json");
    EXPECT_EQ(row.overrides, (std::vector<std::string>{"camera.width=32", "lights.0.scale=2",
                                                       "lights.0.spectrum=illuminants/D65"}));
    EXPECT_EQ(row.render["mode"], "rgb");
    EXPECT_EQ(row.where.key, "rows.0");
    // The canonical settings: render keys sorted, so the same job written differently has one id.
    EXPECT_EQ(row.settings().dump(),
              R"({"scene":"c.json","set":["camera.width=32","lights.0.scale=2","lights.0.spectrum=illuminants/D65"],)"
              R"("render":{"detector":"cie1931","mode":"rgb","write":["png","xyz"]}})");
}

TEST(Sweep, ManifestsInJsonLinesAndCsvGiveTheSameJobs) {
    const Sweep jsonl = readSweep(write("m.jsonl", R"({"scene": "a.json", "set": {"lights.0.spectrum": "illuminants/A"}, "render": {"bits": 16, "size": "64x48"}}

{"scene": "b.json", "render": {"write": ["png"], "half": true}}
)"));
    const Sweep csv = readSweep(write("m.csv", "scene,set:lights.0.spectrum,bits,size,write,half\n"
                                               "a.json,illuminants/A,16,64x48,,\n"
                                               "b.json,,,,\"png\",true\n"));
    ASSERT_EQ(jsonl.size(), 2u);
    ASSERT_EQ(csv.size(), 2u);
    for (size_t i = 0; i < 2; ++i) EXPECT_EQ(jsonl.job(i).settings(), csv.job(i).settings()) << i;
    EXPECT_EQ(jsonl.job(1).origin, "line 3");
    EXPECT_EQ(csv.job(1).origin, "line 3");
    // A quoted CSV field may hold commas: several outputs in one cell.
    const Sweep quoted = readSweep(write("q.csv", "scene,write\na.json,\"png,xyz\"\n"));
    EXPECT_EQ(quoted.job(0).render["write"], Json::array({"png", "xyz"}));
}

TEST(Sweep, MistakesNameTheFileTheKeyOrLineAndWhatWasExpected) {
    std::string e = errorOf("s1.json", R"({"scenes": ["a.json"], "axis": []})");
    EXPECT_NE(e.find("s1.json: axis: unknown sweep key 'axis' (did you mean 'axes'?)"), std::string::npos) << e;
    e = errorOf("s2.json", R"({"scenes": ["a.json"], "render": {"detectr": "cie1931"}})");
    EXPECT_NE(e.find("render.detectr: unknown render setting 'detectr' (did you mean 'detector'?)"), std::string::npos)
        << e;
    e = errorOf("s3.json", R"({"scenes": ["a.json"], "axes": [{"set": "x", "render": "mode", "values": [1]}]})");
    EXPECT_NE(e.find("axes.0: an axis varies either"), std::string::npos) << e;
    e = errorOf("s4.json", R"({"scenes": ["a.json"], "axes": [{"set": "lights.0.scale", "values": []}]})");
    EXPECT_NE(e.find("axes.0.values: expected a non-empty array"), std::string::npos) << e;
    e = errorOf("s5.json", R"({"scenes": ["a.json"], "axes": [{"render": "bits", "values": [8, "16"]}]})");
    EXPECT_NE(e.find("axes.0.values.1: expected an integer, got a string"), std::string::npos) << e;
    e = errorOf("s6.json", R"({"rows": [{"set": ["a=1"]}]})");
    EXPECT_NE(e.find("rows.0.scene: every job needs \"scene\""), std::string::npos) << e;
    e = errorOf("s7.json", R"({"set": ["camera.width"], "scenes": ["a.json"]})");
    EXPECT_NE(e.find("KEY=VALUE"), std::string::npos) << e;
    e = errorOf("s8.json", R"({"out": "x"})");
    EXPECT_NE(e.find("no jobs"), std::string::npos) << e;
    e = errorOf("s9.json", "{\"scenes\": [\"a.json\"],");
    EXPECT_NE(e.find("s9.json:1: "), std::string::npos) << e;
    EXPECT_NE(e.find("JSON syntax error"), std::string::npos) << e;
    e = errorOf("m1.csv", "scene,detectr\na.json,cie1931\n");
    EXPECT_NE(e.find("m1.csv:1: column 2: unknown column 'detectr' (did you mean 'detector'?)"), std::string::npos) << e;
    e = errorOf("m2.csv", "scene,bits\na.json,16\nb.json,16,extra\n");
    EXPECT_NE(e.find("m2.csv:3: 3 fields where the header has 2 columns"), std::string::npos) << e;
    e = errorOf("m3.csv", "scene,bits\na.json,sixteen\n");
    EXPECT_NE(e.find("m3.csv:2: bits: expected an integer, got 'sixteen'"), std::string::npos) << e;
    e = errorOf("m4.jsonl", "{\"scene\": \"a.json\"}\n{\"scene\": \"b.json\", \"render\": {\"half\": 1}}\n");
    EXPECT_NE(e.find("m4.jsonl:2: render.half: expected true or false, got a number"), std::string::npos) << e;
    e = errorOf("m5.txt", "scene\n");
    EXPECT_NE(e.find("expected a sweep file (.json) or a manifest (.jsonl, .csv)"), std::string::npos) << e;
    // Values are checked when a job is made: the size, with the job's origin.
    const Sweep s = readSweep(write("s10.json", R"({"scenes": ["a.json"], "axes": [{"render": "size", "values": ["64x64", "64by64"]}]})"));
    EXPECT_NO_THROW(makeRenderJob(s, s.job(0), "out"));
    try {
        makeRenderJob(s, s.job(1), "out");
        ADD_FAILURE() << "no error";
    } catch (const Error& err) {
        EXPECT_NE(std::string(err.what()).find("s10.json: scenes.0.render.size: scenes.0 × size=64by64: '64by64' for size: "
                                               "expected WIDTHxHEIGHT"),
                  std::string::npos)
            << err.what();
    }
}

TEST(Sweep, RenderJobsCarryEverySetting) {
    const Sweep s = readSweep(write("s11.json", R"({"scenes": ["sub/a.json"], "render": {
        "detector": "camera:nikon_d5100", "adapt": "cat16", "display": "crt", "bits": 16, "integration": "trapezoid",
        "xyz": "absolute", "mode": "ac1c2:8", "grid": "380:780:10", "resample": "sprague", "write": "png,responses",
        "size": "40x30", "ssaa": 2, "half": true, "compression": "zip", "backend": "cpu", "strict_coverage": true}})"));
    const RenderJob j = makeRenderJob(s, s.job(0), "out/x");
    EXPECT_EQ(j.scene, s.folder / "sub/a.json");
    EXPECT_EQ(j.outDir, "out/x");
    EXPECT_EQ(*j.detector, "camera:nikon_d5100");
    EXPECT_EQ(*j.adaptation, "cat16");
    EXPECT_EQ(*j.display, "crt");
    EXPECT_EQ(*j.bits, 16);
    EXPECT_EQ(*j.integration, "trapezoid");
    EXPECT_EQ(*j.xyz, "absolute");
    EXPECT_EQ(j.mode, "ac1c2:8");
    EXPECT_EQ(j.grid->str(), "380:780:10");
    EXPECT_EQ(*j.resampling, Resampling::Sprague);
    EXPECT_EQ(*j.write, (std::vector<std::string>{"png", "responses"}));
    EXPECT_EQ(j.overrides, (std::vector<std::string>{"camera.width=40", "camera.height=30"}));
    EXPECT_EQ(j.ssaa, 2);
    EXPECT_TRUE(j.half);
    EXPECT_EQ(j.compression, "zip");
    EXPECT_EQ(j.backend, Backend::Cpu);
    EXPECT_EQ(j.coverage, CoveragePolicy::Error);
}

TEST(Sweep, ASensorJobWritesItsCubeAndCarriesItsCapture) {
    const Sweep s = readSweep(write("s12.json", R"({"scenes": ["a.json"], "render": {"write": "png",
        "sensor": "sensors/mine.json", "seed": 7, "frames": 3, "exposure": 0.004}})"));
    const RenderJob j = makeRenderJob(s, s.job(0), "out/x");
    EXPECT_EQ(*j.write, (std::vector<std::string>{"png"}));  // as the sweep says, and
    EXPECT_TRUE(j.writeCube);                                  // the cube besides: the capture reads it
    const std::optional<CaptureRequest> c = makeCaptureRequest(s, s.job(0));
    ASSERT_TRUE(c.has_value());
    EXPECT_EQ(c->sensor, (s.folder / "sensors/mine.json").string());
    EXPECT_EQ(c->seed, 7u);
    EXPECT_EQ(c->frames, 3);
    EXPECT_EQ(*c->exposure, 0.004);
    const Sweep library = readSweep(write("s13.json", R"({"scenes": ["a.json"], "render": {"sensor": "aps_c_rggb"}})"));
    EXPECT_EQ(makeCaptureRequest(library, library.job(0))->sensor, "aps_c_rggb");
    // Without a write list the scene's output.write stands (its ground truth, say): only the cube is added.
    EXPECT_FALSE(makeRenderJob(library, library.job(0), "out").write.has_value());
    EXPECT_TRUE(makeRenderJob(library, library.job(0), "out").writeCube);
    const Sweep plain = readSweep(write("s14.json", R"({"scenes": ["a.json"]})"));
    EXPECT_FALSE(makeCaptureRequest(plain, plain.job(0)).has_value());
    // A seed without a sensor, or a bad value, names the key.
    const Sweep lone = readSweep(write("s15.json", R"({"scenes": ["a.json"], "render": {"seed": 3}})"));
    try {
        makeRenderJob(lone, lone.job(0), "out");
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("render.seed"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("'seed' goes with 'sensor'"), std::string::npos) << e.what();
    }
    const Sweep zero = readSweep(write("s16.json", R"({"scenes": ["a.json"], "render": {"sensor": "x", "frames": 0}})"));
    EXPECT_THROW(makeRenderJob(zero, zero.job(0), "out"), Error);
    EXPECT_NE(errorOf("s17.json", R"({"scenes": ["a.json"], "render": {"exposure": "long"}})").find("expected a number"),
              std::string::npos);
}

// Issue 30, class 9: what a sweep used to accept silently is an error naming its key, line or
// variable; a spreadsheet's byte-order mark is not.
TEST(Sweep, NothingIsAcceptedSilently) {
    std::string e = errorOf("d1.json", R"({"scenes": ["a.json"], "scenes": ["b.json"]})");
    EXPECT_NE(e.find("duplicate key"), std::string::npos) << e;
    e = errorOf("d2.json", R"({"scenes": ["a.json"], "axes": [{"name": 5, "render": "bits", "values": [8]}]})");
    EXPECT_NE(e.find("axes.0.name: expected the axis's name, a non-empty string; got a number"), std::string::npos) << e;
    e = errorOf("d3.csv", "scene,bits,bits\na.json,8,16\n");
    EXPECT_NE(e.find("d3.csv:1: column 3: 'bits' is column 2 too"), std::string::npos) << e;
    const Sweep bom = readSweep(write("d4.csv", "\xEF\xBB\xBFscene,bits\na.json,8\n"));
    ASSERT_EQ(bom.size(), 1u);
    EXPECT_EQ(bom.job(0).scene, "a.json");
    for (const char* size : {"4294967304x8", "8x4294967304", "-8x8", "8x", "0x8", "65537x1", "8x8x8", " 8x8"}) {
        const Sweep s = readSweep(write("d5.json", fmt::format(R"({{"scenes": ["a.json"], "render": {{"size": "{}"}}}})", size)));
        EXPECT_THROW(makeRenderJob(s, s.job(0), "out"), Error) << size;
    }
    const Sweep ok = readSweep(write("d6.json", R"({"scenes": ["a.json"], "render": {"size": "65536X2"}})"));
    EXPECT_EQ(makeRenderJob(ok, ok.job(0), "out").overrides, (std::vector<std::string>{"camera.width=65536", "camera.height=2"}));
    e = errorOf("d7.jsonl", "{\"scene\": \"a.json\", \"scene\": \"b.json\"}\n");
    EXPECT_NE(e.find("d7.jsonl:1: not a JSON object on one line"), std::string::npos) << e;
    EXPECT_NE(e.find("duplicate key"), std::string::npos) << e;
}

namespace {

// An axis of `n` numeric values 1..n for a scene key.
std::string numberAxis(const std::string& name, int n) {
    std::vector<int> v(n);
    for (int i = 0; i < n; ++i) v[i] = i + 1;
    return fmt::format(R"({{"name": "{}", "set": "lights.0.scale", "values": [{}]}})", name, fmt::join(v, ","));
}

}  // namespace

// Issue 30, class 1: a sweep is counted when it is read (with overflow checks) and refused above
// kMaxSweepJobs, naming its axes; below that its jobs are made one at a time, so job k of a large
// sweep is there without the others existing.
TEST(Sweep, IsCountedBeforeAnyJobExistsAndMadeOneJobAtATime) {
    std::string e = errorOf("n1.json", fmt::format(R"({{"scenes": ["a.json"], "axes": [{}, {}, {}]}})",
                                                   numberAxis("x", 1000), numberAxis("y", 1000), numberAxis("z", 1000)));
    EXPECT_NE(e.find("n1.json: axes: the sweep has 1e+09 jobs (1 base job(s) × x (1000 values) × y (1000 values) × z "
                     "(1000 values)), more than the limit of 1000000"),
              std::string::npos)
        << e;
    // 256⁸ = 2⁶⁴ wraps a 64-bit count around to 0: refused all the same.
    std::vector<std::string> axes;
    for (int a = 0; a < 8; ++a) axes.push_back(numberAxis(fmt::format("a{}", a), 256));
    e = errorOf("n2.json", fmt::format(R"({{"scenes": ["a.json"], "axes": [{}]}})", fmt::join(axes, ", ")));
    EXPECT_NE(e.find("the sweep has 1.84e+19 jobs"), std::string::npos) << e;

    // 2 scenes × 200 × 200: 80 000 jobs, counted, and job k decoded from k alone (last axis fastest).
    const Sweep s = readSweep(write("n3.json", fmt::format(R"({{"scenes": ["a.json", "b.json"], "axes": [{}, {}]}})",
                                                          numberAxis("x", 200), numberAxis("y", 200))));
    ASSERT_EQ(s.size(), 80000u);
    const SweepJob last = s.job(79999);
    EXPECT_EQ(last.scene, "b.json");
    EXPECT_EQ(last.overrides, (std::vector<std::string>{"lights.0.scale=200", "lights.0.scale=200"}));
    const SweepJob k = s.job(40000 + 3 * 200 + 7);
    EXPECT_EQ(k.scene, "b.json");
    EXPECT_EQ(k.overrides, (std::vector<std::string>{"lights.0.scale=4", "lights.0.scale=8"}));
    EXPECT_EQ(k.origin, "scenes.1 × x=4, y=8");
    EXPECT_THROW(s.job(80000), Error);
}

// Issue 30, class 5: two jobs that render the same thing are refused when the sweep is read — so
// in every mode (--list, --dry-run, --slurm, each shard), not only by a run that reaches them.
TEST(Sweep, TwoJobsThatRenderTheSameThingAreRefusedWhenTheSweepIsRead) {
    std::string e = errorOf("u1.json", R"({"scenes": ["a.json"], "axes": [{"render": "bits", "values": [8, 10, 8]}]})");
    EXPECT_NE(e.find("jobs 1 (scenes.0 × bits=8) and 3 (scenes.0 × bits=8) render the same thing"), std::string::npos)
        << e;
    // A row that repeats what "scenes" × the axes already make.
    e = errorOf("u2.json", R"({"scenes": ["a.json"], "render": {"bits": 8},
                               "rows": [{"scene": "./a.json", "render": {"bits": 8}}]})");
    EXPECT_NE(e.find("jobs 1 (scenes.0) and 2 (rows.0) render the same thing"), std::string::npos) << e;
    e = errorOf("u3.jsonl", "{\"scene\": \"a.json\"}\n{\"scene\": \"b.json\"}\n{\"scene\": \"a.json\"}\n");
    EXPECT_NE(e.find("u3.jsonl:3: jobs 1 (line 1) and 3 (line 3) render the same thing"), std::string::npos) << e;
    e = errorOf("u4.csv", "scene,bits\na.json,8\na.json,8\n");
    EXPECT_NE(e.find("jobs 1 (line 2) and 2 (line 3)"), std::string::npos) << e;
    // Different settings are different jobs, even when one is the default of the other.
    EXPECT_NO_THROW(readSweep(write("u5.csv", "scene,bits\na.json,8\na.json,\n")));
}

// Issue 49, item 2: random draws. Each job's values come from (seed, its position) alone: reading
// the sweep again gives the same values, the jobs differ, every value lies in its range, a choice
// picks every entry about as often, a folder of spectra is the library's, and the mistakes name
// their keys.
TEST(SweepDraws, EachJobsValuesAreItsOwnReproducibleAndInRange) {
    const std::string text = R"({
  "scenes": ["a.json", "b.json"],
  "axes": [{"name": "detector", "render": "detector", "values": ["cie1931", "cie1964"]}],
  "draws": {"count": 250, "seed": 11, "values": [
    {"name": "light", "set": "lights.0.spectrum",
     "choose": ["illuminants/A", {"daylight_cct": [4000, 10000]}, {"blackbody_k": [2500, 3500]}]},
    {"name": "paint", "set": "materials.patch.diffuse", "choose_spectra": "reflectances/cie_2017_ces"},
    {"set": "lights.0.scale", "uniform": [0.005, 0.02]},
    {"name": "where", "set": "objects.1.center", "uniform": [[-0.1, -0.1, 0], [0.1, 0.1, 0]]}
  ]}
})";
    const Sweep a = readSweep(write("draws.json", text)), b = readSweep(write("draws2.json", text));
    ASSERT_EQ(a.size(), 2u * 2u * 250u);
    std::map<std::string, int> lights;
    std::set<std::string> paints, scales;
    for (size_t p = 0; p < a.size(); ++p) {
        const SweepJob j = a.job(p);
        EXPECT_EQ(j.settings(), b.job(p).settings()) << p;  // the same sweep, the same values
        EXPECT_EQ(j.axes["draw"].get<size_t>(), p % 250);
        const auto& light = j.axes["light"];
        if (light.is_string()) {
            ++lights["A"];
        } else if (light.contains("daylight_cct")) {
            ++lights["daylight"];
            EXPECT_GE(light["daylight_cct"].get<double>(), 4000.0);
            EXPECT_LE(light["daylight_cct"].get<double>(), 10000.0);
        } else {
            ++lights["blackbody"];
            EXPECT_GE(light["blackbody_k"].get<double>(), 2500.0);
            EXPECT_LE(light["blackbody_k"].get<double>(), 3500.0);
        }
        paints.insert(j.axes["paint"].get<std::string>());
        const double scale = j.axes["lights.0.scale"].get<double>();
        EXPECT_GE(scale, 0.005);
        EXPECT_LE(scale, 0.02);
        scales.insert(j.axes["lights.0.scale"].dump());
        const auto& where = j.axes["where"];
        ASSERT_EQ(where.size(), 3u);
        EXPECT_LE(std::abs(where[0].get<double>()), 0.1);
        EXPECT_EQ(where[2].get<double>(), 0.0);
        // The drawn values are the job's last overrides, as the record keeps them.
        EXPECT_EQ(j.overrides.back().rfind("objects.1.center=[", 0), 0u) << j.overrides.back();
    }
    // 1000 jobs, three choices: each about 333 (±3σ = ±45).
    for (const auto& [k, n] : lights) EXPECT_NEAR(n, 1000.0 / 3.0, 45.0) << k;
    EXPECT_EQ(lights.size(), 3u);
    EXPECT_GT(paints.size(), 90u);       // nearly all 99 samples drawn in 1000 tries
    EXPECT_EQ(scales.size(), a.size());  // no two jobs alike
    for (const std::string& p : paints) EXPECT_EQ(p.rfind("reflectances/cie_2017_ces/ces", 0), 0u) << p;
    // Another seed, other values.
    std::string other = text;
    other.replace(other.find("\"seed\": 11"), 10, "\"seed\": 12");
    EXPECT_NE(readSweep(write("draws3.json", other)).job(0).settings(), a.job(0).settings());
}

TEST(SweepDraws, MistakesNameTheirKeys) {
    auto with = [&](const std::string& draws) {
        return errorOf("bad-draws.json", R"({"scenes": ["a.json"], "draws": )" + draws + "}");
    };
    EXPECT_NE(with(R"({"values": [{"set": "k", "uniform": [0, 1]}]})").find("draws.count: missing required key"),
              std::string::npos);
    EXPECT_NE(with(R"({"count": 0, "values": [{"set": "k", "uniform": [0, 1]}]})").find("draws.count"), std::string::npos);
    EXPECT_NE(with(R"({"count": 2, "values": []})").find("draws.values: expected a non-empty array"), std::string::npos);
    EXPECT_NE(with(R"({"count": 2, "values": [{"set": "k"}]})").find("draws.values.0: a drawn value has exactly one of"),
              std::string::npos);
    EXPECT_NE(with(R"({"count": 2, "values": [{"set": "k", "uniform": [2, 1]}]})")
                  .find("draws.values.0.uniform: the lowest (2) is above the highest (1)"),
              std::string::npos);
    EXPECT_NE(with(R"({"count": 2, "values": [{"set": "k", "daylight_cct": [3000, 6000]}]})")
                  .find("draws.values.0.daylight_cct: expected lowest ≤ highest within 4000 … 25000 K"),
              std::string::npos);
    EXPECT_NE(with(R"({"count": 2, "values": [{"set": "k", "choose": ["x", {"blackbody_k": [10, 20]}]}]})")
                  .find("draws.values.0.choose.1.blackbody_k"),
              std::string::npos);
    EXPECT_NE(with(R"({"count": 2, "values": [{"set": "k", "choose_spectra": "reflectances/none"}]})")
                  .find("draws.values.0.choose_spectra: the library has no spectra in 'reflectances/none'"),
              std::string::npos);
    EXPECT_NE(with(R"({"count": 2, "values": [{"set": "k", "uniform": [0, 1], "seed": 3}]})").find("draws.values.0.seed"),
              std::string::npos);
    EXPECT_NE(errorOf("big-draws.json", R"({"scenes": ["a.json", "b.json"],
        "draws": {"count": 600000, "values": [{"set": "k", "uniform": [0, 1]}]}})")
                  .find("the sweep has 1.2e+06 jobs (2 base job(s) × 600000 draws)"),
              std::string::npos);
}

// Directions uniform on the sphere and on a cap (cos α uniform: Archimedes), rotations uniform over
// all orientations — applied through the scene's own convention M = Rz·Ry·Rx (built here with glm),
// they carry a fixed axis uniformly over the sphere. 4000 draws: fractions within 3σ.
TEST(SweepDraws, DirectionsAndRotationsAreUniform) {
    const SweepDraws d = readSweepDraws(Json::parse(R"({"count": 4000, "seed": 3, "values": [
        {"name": "any", "set": "objects.0.normal", "direction": {}},
        {"name": "cap", "set": "objects.1.normal", "direction": {"around": [0, 2, 0], "within_deg": 60}},
        {"name": "turn", "set": "objects.2.rotate_deg", "rotation": "uniform"}]})"), Where{"draws.json", "draws"},
                                        SpectrumLibrary());
    const int n = 4000;
    const double band = 3.0 * std::sqrt(0.25 * 0.75 / n);  // 3σ of a fraction near 1/4
    int anyHigh = 0, capHigh = 0, turnedHigh = 0;
    glm::dvec3 anyMean(0.0), turnedMean(0.0);
    for (int p = 0; p < n; ++p) {
        const std::vector<DrawnValue> v = drawValues(d, uint64_t(p));
        ASSERT_EQ(v.size(), 3u);
        const glm::dvec3 any(v[0].value[0].get<double>(), v[0].value[1].get<double>(), v[0].value[2].get<double>());
        const glm::dvec3 cap(v[1].value[0].get<double>(), v[1].value[1].get<double>(), v[1].value[2].get<double>());
        ASSERT_NEAR(glm::length(any), 1.0, 1e-12);
        ASSERT_NEAR(glm::length(cap), 1.0, 1e-12);
        ASSERT_GE(cap.y, 0.5 - 1e-12) << "within 60° of +y";
        anyMean += any / double(n);
        anyHigh += any.z > 0.5;
        capHigh += cap.y > 0.75;  // cos α uniform in [0.5, 1]: half above 0.75
        const double rad = 3.14159265358979323846 / 180.0;
        glm::dmat4 m(1.0);
        m = glm::rotate(m, v[2].value[2].get<double>() * rad, glm::dvec3(0, 0, 1));
        m = glm::rotate(m, v[2].value[1].get<double>() * rad, glm::dvec3(0, 1, 0));
        m = glm::rotate(m, v[2].value[0].get<double>() * rad, glm::dvec3(1, 0, 0));
        const glm::dvec3 turned = glm::dvec3(m * glm::dvec4(0, 0, 1, 0));
        turnedMean += turned / double(n);
        turnedHigh += turned.z > 0.5;
    }
    const double meanBand = 3.0 * std::sqrt(1.0 / 3.0 / n);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(anyMean[c], 0.0, meanBand) << c;
        EXPECT_NEAR(turnedMean[c], 0.0, meanBand) << c;
    }
    EXPECT_NEAR(anyHigh / double(n), 0.25, band);
    EXPECT_NEAR(turnedHigh / double(n), 0.25, band);
    EXPECT_NEAR(capHigh / double(n), 0.5, 3.0 * std::sqrt(0.25 / n));
    auto error = [](const std::string& value) {
        try {
            readSweepDraws(Json::parse(R"({"count": 2, "values": [{"set": "k", )" + value + "}]}"), Where{"d.json", "draws"},
                           SpectrumLibrary());
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(error(R"("direction": {"within_deg": 0})").find("draws.values.0.direction.within_deg"), std::string::npos);
    EXPECT_NE(error(R"("direction": {"around": [0, 0, 0]})").find("draws.values.0.direction.around: expected a non-zero"),
              std::string::npos);
    EXPECT_NE(error(R"("direction": {"axis": [0, 0, 1]})").find("draws.values.0.direction"), std::string::npos);
    EXPECT_NE(error(R"("rotation": "random")").find("draws.values.0.rotation: expected \"uniform\""), std::string::npos);
}

TEST(SweepDraws, DrawsThatPickTheSameValuesAreStillTwoJobs) {
    // Sampling with replacement: 10 draws from two lights repeat values, and every draw is a job.
    const Sweep s = readSweep(write("repeat.json", R"({"scenes": ["a.json"],
        "draws": {"count": 10, "values": [{"set": "lights.0.spectrum", "choose": ["illuminants/A", "illuminants/D65"]}]}})"));
    ASSERT_EQ(s.size(), 10u);
    std::set<std::string> settings;
    for (size_t p = 0; p < s.size(); ++p) settings.insert(s.job(p).settings().dump());
    EXPECT_EQ(settings.size(), 10u);
}

// The bundled training-set sweep (scenes/dataset/, issue 49, item 3) reads: 10 000 jobs, each with its
// draws as overrides of the base scene's keys.
TEST(SweepDraws, TheBundledDatasetSweepReads) {
    const Sweep s = readSweep(fs::path(METAMER_SOURCE_DIR) / "scenes" / "dataset" / "sweep.json");
    ASSERT_EQ(s.size(), 10000u);
    ASSERT_TRUE(s.draws.has_value());
    for (size_t p : {size_t(0), size_t(4321), size_t(9999)}) {
        const SweepJob j = s.job(p);
        EXPECT_EQ(j.axes["draw"].get<size_t>(), p);
        EXPECT_EQ(j.overrides.size(), s.draws->values.size());
        EXPECT_EQ(j.axes["reflectance2"].get<std::string>().rfind("reflectances/pmc/", 0), 0u);
    }
}
