// metamer batch's runner (batch/batch): job ids from settings and input content, one device for
// every job, records that make a rerun skip what is done, failures recorded without stopping the
// batch, shards that partition the jobs, and an index rebuilt from what is on disk.
#include "batch/batch.h"

#include "support/gpu.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sys/stat.h>
#include <unistd.h>

using namespace metamer;
using namespace metamer::test;
namespace fs = std::filesystem;

namespace {

// A folder with a scene that reads a spectrum of its own (paint.csv) and one that does not.
struct Fixture {
    fs::path dir;
    Fixture() {
        dir = fs::temp_directory_path() / fmt::format("metamer-batch-test-{}-{}", ::getpid(),
                                                      ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir);
        fs::create_directories(dir);
        writePaint(0.5);
        std::ofstream(dir / "painted.json") << R"({
  "grid": {"start_nm": 380, "end_nm": 780, "step_nm": 10},
  "camera": {"projection": "orthographic", "position": [0, 0, 1], "target": [0, 0, 0], "up": [0, 1, 0],
             "height_m": 1, "width": 16, "height": 16},
  "lights": [{"type": "directional", "direction": [0, 0, -1], "spectrum": "illuminants/D65"}],
  "materials": {"paint": {"diffuse": "paint.csv"}},
  "objects": [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [2, 2], "material": "paint"}]
})";
        std::ofstream(dir / "grey.json") << R"({
  "grid": {"start_nm": 380, "end_nm": 780, "step_nm": 10},
  "camera": {"projection": "orthographic", "position": [0, 0, 1], "target": [0, 0, 0], "up": [0, 1, 0],
             "height_m": 1, "width": 16, "height": 16},
  "lights": [{"type": "directional", "direction": [0, 0, -1], "spectrum": "illuminants/D65"}],
  "materials": {"grey": {"diffuse": 0.4}},
  "objects": [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [2, 2], "material": "grey"}]
})";
    }
    ~Fixture() { fs::remove_all(dir); }
    void writePaint(double v) const {
        std::ofstream f(dir / "paint.csv");
        f << "wavelength_nm,value\n380," << v << "\n780," << v << "\n";
    }
    fs::path sweep(const std::string& text, const std::string& name = "sweep.json") const {
        std::ofstream(dir / name) << text;
        return dir / name;
    }
};

const char* kTwoByThree = R"({
  "scenes": ["painted.json", "grey.json"],
  "render": {"write": "png,xyz"},
  "axes": [{"name": "light", "set": "lights.0.spectrum", "values": ["illuminants/D65", "illuminants/A", "illuminants/FL2"]}]
})";

BatchOptions options(const fs::path& out, int shard = 0, int shards = 1) {
    BatchOptions o;
    o.out = out;
    o.shard = shard;
    o.shards = shards;
    o.validation = true;
    return o;
}

std::vector<std::string> ids(const Sweep& s, const fs::path& out) {
    std::vector<std::string> v;
    for (size_t i = 0; i < s.size(); ++i) v.push_back(resolveJob(s, i, out).id);
    return v;
}

std::string bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

}  // namespace

TEST(Batch, ShardsPartitionTheJobsInBalancedDeterministicSubsets) {
    for (size_t jobs : {0u, 1u, 7u, 16u, 1001u})
        for (int shards : {1, 2, 3, 4, 16}) {
            std::vector<int> owner(jobs, -1);
            size_t smallest = jobs, largest = 0;
            for (int s = 0; s < shards; ++s) {
                const std::vector<size_t> p = shardPositions(jobs, s, shards);
                EXPECT_EQ(p, shardPositions(jobs, s, shards));
                smallest = std::min(smallest, p.size());
                largest = std::max(largest, p.size());
                for (size_t k : p) {
                    EXPECT_EQ(owner[k], -1) << "job " << k << " in two shards";
                    owner[k] = s;
                }
            }
            EXPECT_EQ(std::count(owner.begin(), owner.end(), -1), 0);
            EXPECT_LE(largest - smallest, 1u);
        }
    EXPECT_EQ(parseShard("2/4"), std::make_pair(2, 4));
    for (const char* bad : {"4/4", "x/4", "2", "-1/3", "1/0"}) EXPECT_THROW(parseShard(bad), Error) << bad;
    ::setenv("SLURM_ARRAY_TASK_ID", "7", 1);
    ::setenv("SLURM_ARRAY_TASK_MIN", "5", 1);
    ::setenv("SLURM_ARRAY_TASK_COUNT", "4", 1);
    EXPECT_EQ(parseShard(""), std::make_pair(2, 4));
    EXPECT_EQ(parseShard("0/1"), std::make_pair(0, 1));  // the flag wins
    ::setenv("SLURM_ARRAY_TASK_ID", "9", 1);
    EXPECT_THROW(parseShard(""), Error);
    ::unsetenv("SLURM_ARRAY_TASK_ID");
    ::unsetenv("SLURM_ARRAY_TASK_MIN");
    // A task id without a count (or a count without an id) would make every task render every
    // job: an error naming the missing variable (issue 30, class 9).
    try {
        parseShard("");
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("SLURM_ARRAY_TASK_ID: is not set but SLURM_ARRAY_TASK_COUNT is"),
                  std::string::npos)
            << e.what();
    }
    ::unsetenv("SLURM_ARRAY_TASK_COUNT");
    ::setenv("SLURM_ARRAY_TASK_ID", "3", 1);
    EXPECT_THROW(parseShard(""), Error);
    EXPECT_EQ(parseShard("1/2"), std::make_pair(1, 2));  // the flag still chooses
    ::unsetenv("SLURM_ARRAY_TASK_ID");
    EXPECT_EQ(parseShard(""), std::make_pair(0, 1));
}

TEST(Batch, IdsDependOnSettingsAndInputContentNotOnWhereTheFilesAre) {
    Fixture f;
    const Sweep s = readSweep(f.sweep(kTwoByThree));
    const std::vector<std::string> a = ids(s, f.dir / "out");
    EXPECT_EQ(std::set<std::string>(a.begin(), a.end()).size(), 6u);
    EXPECT_EQ(a[0].rfind("painted-", 0), 0u);
    EXPECT_EQ(a, ids(s, f.dir / "out"));  // stable
    const ResolvedJob j = resolveJob(s, 0, f.dir / "out");
    EXPECT_EQ(j.render.outDir, f.dir / "out" / j.id);
    EXPECT_TRUE(std::find(j.inputs.begin(), j.inputs.end(), fs::absolute(f.dir / "paint.csv")) != j.inputs.end());
    EXPECT_TRUE(std::find(j.inputs.begin(), j.inputs.end(), fs::absolute(f.dir / "painted.json")) != j.inputs.end());
    // The same files somewhere else: the same ids.
    const fs::path moved = f.dir.string() + "-moved";
    fs::remove_all(moved);
    fs::copy(f.dir, moved, fs::copy_options::recursive);
    EXPECT_EQ(ids(readSweep(moved / "sweep.json"), moved / "out"), a);
    fs::remove_all(moved);
    // Editing the painted scene's spectrum changes its jobs' ids and no others.
    f.writePaint(0.25);
    const std::vector<std::string> b = ids(s, f.dir / "out");
    for (size_t i = 0; i < 3; ++i) EXPECT_NE(a[i], b[i]) << i;
    for (size_t i = 3; i < 6; ++i) EXPECT_EQ(a[i], b[i]) << i;
}

TEST(Batch, RendersEveryJobOnOneDeviceThenSkipsWhatIsDoneAndRendersWhatIsMissing) {
    Fixture f;
    const uint32_t before = gpu().validationErrors();
    const Sweep s = readSweep(f.sweep(kTwoByThree));
    const fs::path out = f.dir / "out";
    std::vector<std::string> lines;
    const BatchSummary first = runBatch(s, options(out), gpu(), [&](const BatchProgress& p) { lines.push_back(p.line); });
    EXPECT_EQ(first.jobs, 6u);
    EXPECT_EQ(first.rendered, 6u);
    EXPECT_EQ(first.failed, 0u) << (first.failures.empty() ? "" : first.failures[0]);
    ASSERT_EQ(lines.size(), 6u);
    const std::vector<std::string> jobIds = ids(s, out);
    for (const std::string& id : jobIds) {
        const std::optional<JobRecord> r = readJobRecord(out / id);
        ASSERT_TRUE(r) << id;
        EXPECT_EQ(r->status, JobStatus::Done);
        EXPECT_TRUE(fs::exists(out / id / (id.rfind("painted", 0) == 0 ? "painted.png" : "grey.png")));
        EXPECT_EQ(r->json["outputs"].size(), 2u);
    }
    // Under A the painted quad's XYZ differs from D65's: the axis reached the scene.
    EXPECT_NE(bytes(out / jobIds[0] / "painted.xyz.exr"), bytes(out / jobIds[1] / "painted.xyz.exr"));

    const BatchSummary again = runBatch(s, options(out), gpu());
    EXPECT_EQ(again.rendered, 0u);
    EXPECT_EQ(again.skipped, 6u);
    // A missing output, a damaged record, a stale temporary file: that job alone is rendered again.
    fs::remove(out / jobIds[2] / "painted.png");
    std::ofstream(out / jobIds[4] / "job.json") << "{ damaged";
    std::ofstream(out / jobIds[5] / ".grey.png.tmp-99999-0.png") << "half";
    fs::remove(out / jobIds[5] / "job.json");
    const BatchSummary third = runBatch(s, options(out), gpu());
    EXPECT_EQ(third.rendered, 3u);
    EXPECT_EQ(third.skipped, 3u);
    EXPECT_TRUE(fs::exists(out / jobIds[2] / "painted.png"));
    EXPECT_FALSE(fs::exists(out / jobIds[5] / ".grey.png.tmp-99999-0.png"));
    EXPECT_NO_VALIDATION_ERRORS(before);
}

TEST(Batch, AJobThatFailsWhileRenderingIsRecordedAndTheOthersRender) {
    Fixture f;
    const uint32_t before = gpu().validationErrors();
    const Sweep s = readSweep(f.sweep(R"({"scenes": ["grey.json"], "render": {"write": "png"},
        "axes": [{"render": "size", "values": ["8x8", "10x8", "12x8"]}]})"));
    const fs::path out = f.dir / "out";
    // The second job's PNG cannot be put in place (a folder is in the way): it loads, renders, and
    // fails to commit its output.
    const std::string failedId = resolveJob(s, 1, out).id;
    fs::create_directories(out / failedId / "grey.png" / "in-the-way");
    const BatchSummary r = runBatch(s, options(out), gpu());
    EXPECT_EQ(r.rendered, 2u);
    EXPECT_EQ(r.failed, 1u);
    ASSERT_EQ(r.failures.size(), 1u);
    EXPECT_EQ(r.failures[0].rfind(failedId + ": ", 0), 0u) << r.failures[0];
    const std::optional<JobRecord> rec = readJobRecord(out / failedId);
    ASSERT_TRUE(rec);
    EXPECT_EQ(rec->status, JobStatus::Failed);
    EXPECT_NE(rec->error.find("grey.png"), std::string::npos) << rec->error;
    // A rerun leaves it failed (and says so) unless asked to retry.
    const BatchSummary rerun = runBatch(s, options(out), gpu());
    EXPECT_EQ(rerun.rendered, 0u);
    EXPECT_EQ(rerun.skipped, 2u);
    EXPECT_EQ(rerun.failed, 1u);
    BatchOptions retry = options(out);
    retry.retryFailed = true;
    const BatchSummary retried = runBatch(s, retry, gpu());
    EXPECT_EQ(retried.failed, 1u);
    EXPECT_EQ(retried.skipped, 2u);
    // The index holds all three, the failure with its error.
    const IndexSummary failedIndex = writeBatchIndex(out);
    EXPECT_EQ(failedIndex.records, 3u);
    EXPECT_EQ(failedIndex.failed, 1u);
    // Once the cause is gone, --retry-failed renders it.
    fs::remove_all(out / failedId / "grey.png");
    const BatchSummary fixed = runBatch(s, retry, gpu());
    EXPECT_EQ(fixed.rendered, 1u);
    EXPECT_EQ(fixed.failed, 0u);
    const IndexSummary i = writeBatchIndex(out);
    EXPECT_EQ(i.records, 3u);
    EXPECT_EQ(i.done, 3u);
    EXPECT_NO_VALIDATION_ERRORS(before);
}

TEST(Batch, AJobThatCannotLoadStopsTheBatchBeforeAnythingRenders) {
    Fixture f;
    const Sweep s = readSweep(f.sweep(R"({"scenes": ["grey.json", "painted.json"],
        "axes": [{"name": "light", "set": "lights.0.spectrum", "values": ["illuminants/D65", "illuminants/D66"]}]})"));
    const fs::path out = f.dir / "out";
    try {
        runBatch(s, options(out), gpu());
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        const std::string m = e.what();
        EXPECT_NE(m.find("sweep.json: scenes.0: job 2 of 4 (scenes.0 × light=illuminants/D66) cannot be rendered: "),
                  std::string::npos)
            << m;
        EXPECT_NE(m.find("grey.json: lights.0.spectrum"), std::string::npos) << m;
        EXPECT_NE(m.find("illuminants/D65"), std::string::npos) << m;  // the suggestion
    }
    EXPECT_FALSE(fs::exists(out));
}

// A FIFO where a job's record goes (issue 51, class 10): found when the jobs are resolved — by the
// run before its first render, and by --dry-run — as bad input naming it, not a failed job after
// its render.
TEST(Batch, AFifoWhereARecordGoesStopsTheBatchBeforeAnythingRenders) {
    Fixture f;
    const Sweep s = readSweep(f.sweep(R"({"scenes": ["grey.json"]})"));
    const fs::path out = f.dir / "out";
    const ResolvedJob j = resolveJob(s, 0, out);
    fs::create_directories(j.render.outDir);
    ASSERT_EQ(::mkfifo((j.render.outDir / "job.json").c_str(), 0600), 0);
    try {
        runBatch(s, options(out), gpu());
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(e.text().find("job.json: a FIFO is where the job's record goes"), std::string::npos) << e.text();
    }
    EXPECT_THROW(resolveJob(s, 0, out), Error);
    EXPECT_EQ(std::distance(fs::directory_iterator(j.render.outDir), fs::directory_iterator()), 1);  // nothing rendered
}

// A job with a sensor in a channel mode (issue 51, class 4): refused when the jobs are resolved —
// by --dry-run and before the run's first render — not after its render found no cube.
TEST(Batch, ASensorInAChannelModeIsRefusedBeforeAnythingRenders) {
    Fixture f;
    const Sweep s = readSweep(f.sweep(R"({"scenes": ["grey.json"], "render": {"sensor": "aps_c_rggb", "mode": "rgb"}})"));
    try {
        resolveJob(s, 0, f.dir / "out");
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(e.text().find("render.mode: 'rgb' renders channels, not spectra; a sensor captures a spectral cube"),
                  std::string::npos)
            << e.text();
    }
    EXPECT_THROW(runBatch(s, options(f.dir / "out"), gpu()), Error);
    EXPECT_FALSE(fs::exists(f.dir / "out"));
}

TEST(Batch, ShardsRenderDisjointJobsWhoseUnionIsTheWholeBatchFileForFile) {
    Fixture f;
    const uint32_t before = gpu().validationErrors();
    const Sweep s = readSweep(f.sweep(kTwoByThree));
    const fs::path whole = f.dir / "whole", sharded = f.dir / "sharded";
    runBatch(s, options(whole), gpu());
    size_t rendered = 0;
    for (int shard = 0; shard < 4; ++shard) rendered += runBatch(s, options(sharded, shard, 4), gpu()).rendered;
    EXPECT_EQ(rendered, 6u);
    const IndexSummary i = writeBatchIndex(sharded);
    EXPECT_EQ(i.records, 6u);
    for (const std::string& id : ids(s, whole)) {
        const std::string stem = id.substr(0, id.find('-'));
        for (const char* ext : {".png", ".xyz.exr"})
            EXPECT_EQ(bytes(whole / id / (stem + ext)), bytes(sharded / id / (stem + ext))) << id << ext;
        const std::optional<JobRecord> r = readJobRecord(sharded / id);
        ASSERT_TRUE(r);
        EXPECT_NE(r->json["shard"].get<std::string>(), "0/1");
    }
    // The index lists every job in sweep order, one settings column per varied key.
    const std::string csv = bytes(sharded / "index.csv");
    EXPECT_EQ(csv.rfind("id,status,current,error,scene,set:lights.0.spectrum,write,", 0), 0u) << csv.substr(0, 200);
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 7);
    EXPECT_NO_VALIDATION_ERRORS(before);
}

// A job record is input like any other (issue 30, class 3): a FIFO, a record of the wrong types,
// an unknown status or JSON nested past the cap is no record — the job renders again — and reading
// it neither hangs nor throws the JSON library's raw exception.
TEST(Batch, DamagedOrHostileRecordsAreNoRecords) {
    const fs::path dir = fs::temp_directory_path() / ("metamer-records-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    auto record = [&](const std::string& name, const std::string& text) {
        fs::create_directories(dir / name);
        std::ofstream(dir / name / "job.json") << text;
        return dir / name;
    };
    const std::string good = R"({"metamer_batch_record": 1, "id": "a-1", "digest": "ff", "status": "done"})";
    ASSERT_TRUE(readJobRecord(record("good", good)).has_value());
    EXPECT_FALSE(readJobRecord(record("types", R"({"metamer_batch_record": 1, "id": 5, "digest": "ff", "status": "done"})")));
    EXPECT_FALSE(readJobRecord(record("status", R"({"metamer_batch_record": 1, "id": "a", "digest": "ff", "status": "weird"})")));
    EXPECT_FALSE(readJobRecord(record("deep", std::string(100000, '[') + std::string(100000, ']'))));
    EXPECT_FALSE(readJobRecord(record("truncated", good.substr(0, 30))));
    // Every field the index reads, of another type (issue 51, class 10: `--index` printed the
    // JSON library's type_error and exited 1).
    const std::string head = R"({"metamer_batch_record": 1, "id": "b", "digest": "ff", "status": "done", )";
    for (const std::string& field : {R"("position": "3")", R"("position": -1)", R"("settings": 5)",
                                     R"("settings": {"render": []})", R"("settings": {"set": [1]})",
                                     R"("outputs": [7])", R"("outputs": {"file": "x"})", R"("timings_ms": {"job": "x"})",
                                     R"("axes": [1])", R"("finished": 0)", R"("error": 3)"}) {
        EXPECT_FALSE(readJobRecord(record("typed", head + field + "}"))) << field;
        fs::remove_all(dir / "typed");
    }
    record("typed", head + R"("position": "3"})");
    fs::create_directories(dir / "fifo");
    ASSERT_EQ(::mkfifo((dir / "fifo" / "job.json").c_str(), 0600), 0);
    EXPECT_FALSE(readJobRecord(dir / "fifo"));  // returns at once: never opened
    // The index names what it leaves out.
    const IndexSummary index = writeBatchIndex(dir);
    EXPECT_EQ(index.records, 1u);
    EXPECT_EQ(index.unreadable, (std::vector<std::string>{"deep", "fifo", "status", "truncated", "typed", "types"}));
    fs::remove_all(dir);
}
