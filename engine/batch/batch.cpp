#include "batch/batch.h"
#include "batch/job_claim.h"
#include "color/adaptation.h"
#include "color/detector.h"
#include "scene/json_values.h"
#include "spectral/library.h"
#include "sensor/sensor_spec.h"

#include "core/csv_text.h"
#include "core/file_reads.h"
#include "core/statistics.h"
#include "core/timing.h"
#include "io/atomic_file.h"
#include "render/render_setup.h"
#include "represent/representation.h"

#include <fmt/chrono.h>
#include <fmt/ranges.h>
#include <openssl/evp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>
#include <tuple>

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace metamer {

namespace {

constexpr const char* kRecordFile = "job.json";
constexpr int kRecordVersion = 1;

// SHA-256 of `data`, lower-case hex (libcrypto's EVP interface).
class Sha256 {
public:
    Sha256() : ctx_(EVP_MD_CTX_new()) {
        if (!ctx_ || EVP_DigestInit_ex(ctx_, EVP_sha256(), nullptr) != 1) failRuntime("SHA-256 is not available");
    }
    ~Sha256() { EVP_MD_CTX_free(ctx_); }
    Sha256(const Sha256&) = delete;
    Sha256& operator=(const Sha256&) = delete;
    void add(const void* data, size_t n) { EVP_DigestUpdate(ctx_, data, n); }
    void add(const std::string& s) { add(s.data(), s.size()); }
    std::string hex() {
        unsigned char md[EVP_MAX_MD_SIZE];
        unsigned int n = 0;
        EVP_DigestFinal_ex(ctx_, md, &n);
        std::string h;
        for (unsigned int i = 0; i < n; ++i) h += fmt::format("{:02x}", md[i]);
        return h;
    }

private:
    EVP_MD_CTX* ctx_;
};

std::string readDigest(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) failRuntime("cannot read {} to hash it", path.string());
    Sha256 h;
    std::vector<char> buffer(1 << 16);
    while (in) {
        in.read(buffer.data(), std::streamsize(buffer.size()));
        h.add(buffer.data(), size_t(in.gcount()));
    }
    return h.hex();
}

// The digest of a file, kept for the process under its size and modification time: the jobs of a
// sweep read the same library files.
std::string fileDigest(const fs::path& path) {
    static std::map<std::string, std::tuple<uintmax_t, fs::file_time_type, std::string>> cache;
    std::error_code e1, e2;
    const uintmax_t size = fs::file_size(path, e1);
    const auto mtime = fs::last_write_time(path, e2);
    if (e1 || e2) return readDigest(path);
    auto& entry = cache[path.string()];
    if (std::get<2>(entry).empty() || std::get<0>(entry) != size || std::get<1>(entry) != mtime)
        entry = {size, mtime, readDigest(path)};
    return std::get<2>(entry);
}

// The spectra library as a whole (every regular file under its root, by relative path and
// content), once per process: a record says which library its job saw, beyond the files it read.
const std::string& spectraDigest() {
    static const std::string digest = [] {
        const fs::path root = SpectrumLibrary::defaultRoot();
        std::vector<fs::path> files;
        std::error_code ec;
        for (fs::recursive_directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec))
            if (it->is_regular_file(ec)) files.push_back(it->path());
        std::sort(files.begin(), files.end());
        Sha256 h;
        for (const fs::path& f : files) h.add(f.lexically_relative(root).generic_string() + "\n" + fileDigest(f) + "\n");
        return h.hex();
    }();
    return digest;
}

std::string hostName() {
    char h[256] = {};
    return ::gethostname(h, sizeof h - 1) == 0 ? std::string(h) : std::string("?");
}

// UTC to the millisecond: which of two records of one sweep position is later must be decidable
// when both finished within the same second (the index's "current").
std::string utcNow() {
    const auto now = std::chrono::system_clock::now();
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
    return fmt::format("{:%Y-%m-%dT%H:%M:%S}.{:03d}Z", fmt::gmtime(std::chrono::system_clock::to_time_t(now)), int(ms));
}

// Temporary files and staging folders a killed process left in a job's folder (io/atomic_file's
// ".NAME.tmp-PID-N" and ".NAME.staging-PID-N").
void removeStaleTemporaries(const fs::path& folder) {
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) return;
    std::vector<fs::path> stale;
    for (const auto& e : fs::directory_iterator(folder, ec)) {
        const std::string name = e.path().filename().string();
        if ((name.size() > 1 && name[0] == '.' && name.find(".tmp-") != std::string::npos) || isStagingFolderName(name))
            stale.push_back(e.path());
    }
    for (const fs::path& p : stale) fs::remove_all(p, ec);
}

bool outputsExist(const JobRecord& r, const fs::path& folder) {
    if (!r.json.contains("outputs") || !r.json["outputs"].is_array() || r.json["outputs"].empty()) return false;
    std::error_code ec;
    for (const Json& o : r.json["outputs"])
        if (!o.contains("file") || !o["file"].is_string() || !fs::is_regular_file(folder / o["file"].get<std::string>(), ec))
            return false;
    return true;
}

Json recordBase(const Sweep& sweep, const ResolvedJob& j, const BatchOptions& o) {
    Json r = Json::object();
    r["metamer_batch_record"] = kRecordVersion;
    r["id"] = j.id;
    r["digest"] = j.digest;
    r["position"] = j.position;
    r["origin"] = j.origin;
    r["sweep"] = sweep.file.string();
    r["settings"] = j.settings;
    r["axes"] = j.axes;
    r["used"] = j.used;
    r["metamer_version"] = metamerVersion();
    r["spectra_digest"] = spectraDigest();
    Json inputs = Json::array();
    for (const fs::path& p : j.inputs) inputs.push_back(p.string());
    r["inputs"] = inputs;
    r["host"] = hostName();
    r["shard"] = fmt::format("{}/{}", o.shard, o.shards);
    return r;
}

}  // namespace

std::vector<size_t> shardPositions(size_t jobs, int shard, int shards) {
    std::vector<size_t> p;
    for (size_t k = size_t(shard); k < jobs; k += size_t(shards)) p.push_back(k);
    return p;
}

std::pair<int, int> parseShard(const std::string& text) {
    auto parse = [](const std::string& s, const Where& where, const char* what) {
        try {
            size_t used = 0;
            const long v = std::stol(s, &used);
            if (used == s.size() && v >= 0 && v < 1000000) return int(v);
        } catch (const std::exception&) {
        }
        failInput(where, "expected {}, got '{}'", what, s);
    };
    int shard = 0, shards = 1;
    if (!text.empty()) {
        const Where where{"", "--shard"};
        const size_t slash = text.find('/');
        if (slash == std::string::npos) failInput(where, "expected I/N (shard I of N, 0 ≤ I < N), got '{}'", text);
        shard = parse(text.substr(0, slash), where, "I/N with a whole number I");
        shards = parse(text.substr(slash + 1), where, "I/N with a whole number N");
        if (shards < 1 || shard >= shards) failInput(where, "expected I/N with 0 ≤ I < N, got '{}'", text);
        return {shard, shards};
    }
    const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
    const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
    // One without the other would make every task render every job.
    if (bool(id) != bool(count))
        failInput(Where{"", id ? "SLURM_ARRAY_TASK_COUNT" : "SLURM_ARRAY_TASK_ID"},
                  "is not set but {} is: a Slurm array task has both; give --shard I/N to choose a shard by hand",
                  id ? "SLURM_ARRAY_TASK_ID" : "SLURM_ARRAY_TASK_COUNT");
    if (id && count) {
        const char* minText = std::getenv("SLURM_ARRAY_TASK_MIN");
        const int min = minText ? parse(minText, Where{"", "SLURM_ARRAY_TASK_MIN"}, "a task id") : 0;
        shard = parse(id, Where{"", "SLURM_ARRAY_TASK_ID"}, "a task id") - min;
        shards = parse(count, Where{"", "SLURM_ARRAY_TASK_COUNT"}, "a task count");
        if (shards < 1 || shard < 0 || shard >= shards)
            failInput(Where{"", "SLURM_ARRAY_TASK_ID"},
                      "task {} (minimum {}) of {} tasks is not a shard: submit the array as --array=0-{} (or any "
                      "contiguous range)",
                      id, min, count, shards - 1);
    }
    return {shard, shards};
}

ResolvedJob resolveJob(const Sweep& sweep, size_t position, const fs::path& out) {
    const SweepJob sj = sweep.job(position);
    ResolvedJob r;
    r.position = position;
    r.settings = sj.settings();
    r.axes = sj.axes;
    r.origin = sj.origin;
    try {
        r.render = makeRenderJob(sweep, sj, {});
        r.capture = makeCaptureRequest(sweep, sj);
        FileReadLog reads;
        const std::unique_ptr<LoadedScene> loaded = loadJobScene(r.render);
        OutputFiles files;
        const TonemapSettings settings = tonemapSettings(r.render, loaded->scene, &files);
        if (files.png || files.xyz || files.responses) makeJobTonemapPlan(r.render, *loaded, settings);
        // What the job renders with, whether the sweep set it or a default did: the index shows
        // these, not blanks, for settings a job left alone.
        const Camera& camera = loaded->scene.camera;
        r.used = {{"detector", settings.detector},
                  {"adapt", adaptationName(settings.adaptation)},
                  {"integration", integrationName(settings.integration)},
                  {"display", settings.display},
                  {"bits", settings.bits},
                  {"grid", r.render.grid ? r.render.grid->str() : loaded->scene.grid.str()},
                  {"size", fmt::format("{}x{}", camera.width, camera.height)},
                  {"mode", r.render.mode},
                  {"ssaa", r.render.ssaa}};
        r.inputs = reads.files();
        if (r.capture) {
            // A sensor captures a spectral cube: a job in a channel mode would render, then fail
            // (issue 51, class 4); said now, by the run before its first render and by --dry-run.
            requireSpectralModeForSensor(r.render.mode, Where{"", "render.mode"});
            // The sensor is read now, so that a mistake in it stops the batch before any render, and
            // its files join the job's inputs (an edited sensor re-captures the jobs that use it).
            const SpectrumLibrary library;
            const SensorSpec sensor = readSensor(sensorFile(r.capture->sensor, library), library);
            for (const fs::path& p : sensor.inputs)
                if (std::find(r.inputs.begin(), r.inputs.end(), p) == r.inputs.end()) r.inputs.push_back(p);
        }
    } catch (const Error& e) {
        throw Error(e.code(), Where{sweep.file.string(), sj.where.key, sj.where.line},
                    fmt::format("job {} of {} ({}) cannot be rendered: {}", position + 1, sweep.size(),
                                sj.origin, e.text()));
    }
    // The digest: the settings, then the content of every input file, in an order that does not
    // depend on where the files are (so the same sweep has the same ids on every machine).
    std::vector<std::string> contents;
    for (const fs::path& p : r.inputs) contents.push_back(fileDigest(p));
    std::sort(contents.begin(), contents.end());
    Sha256 h;
    h.add(fmt::format("metamer batch job {}\n", kRecordVersion));
    h.add(r.settings.dump());
    for (const std::string& c : contents) h.add("\n" + c);
    r.digest = h.hex();
    r.id = fs::path(sj.scene).stem().string() + "-" + r.digest.substr(0, 16);
    r.render.outDir = out / r.id;
    // Where its record goes must take a file: a FIFO, a device or a folder there would fail the job
    // only after it rendered (issue 51, class 10). Checked with every job, so --dry-run says it too.
    const fs::path record = r.render.outDir / kRecordFile;
    std::error_code ec;
    const fs::file_status status = fs::status(record, ec);
    if (fs::exists(status) && !fs::is_regular_file(status))
        failInput(Where{record.string()}, "{} is where the job's record goes, and a record replaces a file: remove it",
                  specialFileKind(status));
    return r;
}

namespace {

// The fields a resume and the index read, each of its type where present (as recordBase and
// runBatch write them): a record of other types — edited by hand, not ours — is no record, said
// by the index and rendered again, never a type error out of the JSON library.
bool wellTyped(const Json& doc) {
    auto has = [&](const Json& o, const char* key, bool (*test)(const Json&)) { return !o.contains(key) || test(o[key]); };
    auto isString = [](const Json& v) { return v.is_string(); };
    auto isObject = [](const Json& v) { return v.is_object(); };
    auto isStringOrNull = [](const Json& v) { return v.is_string() || v.is_null(); };
    for (const char* key : {"origin", "sweep", "host", "shard", "finished", "metamer_version", "spectra_digest"})
        if (!has(doc, key, isString)) return false;
    if (!has(doc, "error", isStringOrNull)) return false;
    if (!has(doc, "position", [](const Json& v) { return v.is_number_unsigned(); })) return false;
    for (const char* key : {"axes", "used", "timings_ms", "settings"})
        if (!has(doc, key, isObject)) return false;
    if (doc.contains("timings_ms"))
        for (const auto& [k, v] : doc["timings_ms"].items())
            if (!v.is_number()) return false;
    if (doc.contains("outputs")) {
        if (!doc["outputs"].is_array()) return false;
        for (const Json& o : doc["outputs"])
            if (!o.is_object() || !has(o, "file", isString)) return false;
    }
    if (doc.contains("settings")) {
        const Json& settings = doc["settings"];
        if (!has(settings, "render", isObject) || !has(settings, "scene", isString) ||
            !has(settings, "set", [](const Json& v) { return v.is_array(); }))
            return false;
        if (settings.contains("set"))
            for (const Json& o : settings["set"])
                if (!o.is_string()) return false;
    }
    return true;
}

}  // namespace

std::optional<JobRecord> readJobRecord(const fs::path& folder) {
    // A record is input like any other: only a regular file of sane size is read (a FIFO would
    // block, a device never end), with the scene reader's parser (its depth cap), and typed. Anything
    // else — not ours, damaged, of another version — is no record: the job is rendered again.
    const fs::path file = folder / kRecordFile;
    std::error_code ec;
    if (!fs::is_regular_file(file, ec) || fs::file_size(file, ec) > (1u << 20) || ec) return std::nullopt;
    Json doc;
    try {
        doc = json_read::parseJson(readWholeFile(file, Where{file.string()}, "job record"), file.string());
    } catch (const Error&) {
        return std::nullopt;
    }
    auto isString = [&](const char* key) { return doc.contains(key) && doc[key].is_string(); };
    if (!doc.is_object() || doc.value("metamer_batch_record", 0) != kRecordVersion || !isString("id") ||
        !isString("digest") || !isString("status") || (doc["status"] != "done" && doc["status"] != "failed") ||
        !wellTyped(doc))
        return std::nullopt;
    JobRecord r;
    r.id = doc["id"].get<std::string>();
    r.digest = doc["digest"].get<std::string>();
    r.status = doc["status"] == "done" ? JobStatus::Done : JobStatus::Failed;
    if (doc.contains("error") && doc["error"].is_string()) r.error = doc["error"].get<std::string>();
    r.json = std::move(doc);
    return r;
}

BatchSummary runBatch(const Sweep& sweep, const BatchOptions& o, vk::Context& context,
                      const std::function<void(const BatchProgress&)>& progress) {
    const auto start = Clock::now();
    BatchSummary s;
    // Every job of the shard is loaded and checked before the first render.
    std::vector<ResolvedJob> jobs;
    for (size_t position : shardPositions(sweep.size(), o.shard, o.shards)) {
        jobs.push_back(resolveJob(sweep, position, o.out));  // duplicates were refused when the sweep was read
        s.indexed.push_back(indexedJob(jobs.back()));
    }
    s.jobs = jobs.size();
    std::set<std::string> otherVersions;
    BatchProgress p;
    p.total = jobs.size();
    std::vector<double> renderSeconds;
    for (ResolvedJob& j : jobs) {
        const fs::path folder = j.render.outDir;
        auto finished = [&](const std::optional<JobRecord>& record) {
            return record && record->digest == j.digest &&
                   ((record->status == JobStatus::Done && outputsExist(*record, folder)) ||
                    (record->status == JobStatus::Failed && !o.retryFailed));
        };
        std::optional<JobRecord> record = readJobRecord(folder);
        // One writer per job: claimed before its folder's temporaries are cleared or it renders;
        // the record is read again under the claim (another run may have finished it meanwhile).
        std::optional<JobClaim> claim;
        std::string heldBy;
        if (!finished(record)) {
            claim = JobClaim::tryClaim(folder, o.breakClaims, heldBy);
            if (claim) record = readJobRecord(folder);
        }
        if (!finished(record) && !claim) {
            ++s.held;
            ++p.held;
            s.heldBy.push_back(fmt::format("{}: {}", j.id, heldBy));
            p.line = fmt::format("{}: being rendered by {}; left to it", j.id, heldBy);
        } else if (finished(record)) {
            if (record->status == JobStatus::Done) {
                ++s.skipped;
                ++p.skipped;
                p.line = fmt::format("{}: done before, skipped", j.id);
                // Same inputs and settings, but rendered by another Metamer: said, not silently mixed.
                const std::string version = record->json.value("metamer_version", "(before 0.1.0)");
                if (version != metamerVersion()) {
                    ++s.otherVersion;
                    otherVersions.insert(version);
                    p.line += fmt::format(" (rendered by Metamer {})", version);
                }
            } else {
                ++s.failed;
                ++p.failed;
                s.failures.push_back(j.id + ": " + record->error);
                p.line = fmt::format("{}: failed before (--retry-failed renders it again): {}", j.id, record->error);
            }
        } else {
            removeStaleTemporaries(folder);
            const auto t0 = Clock::now();
            Json rec = recordBase(sweep, j, o);
            j.render.context = &context;
            j.render.validation = o.validation;
            try {
                // A sensor's capture reads the cube before anything is renamed into place; its
                // files join the render's, all in place together or none.
                std::optional<StagingFolder> captureStaging;
                CaptureFiles captured;
                RenderJob render = j.render;
                if (j.capture) {
                    captureStaging.emplace(folder, "capture");
                    render.beforeCommit = [&](const std::vector<AtomicOutput*>& files) {
                        captured = stageCaptureOfRender(*j.capture, files, SpectrumLibrary(), *captureStaging);
                        return std::vector<StagingFolder*>{&*captureStaging};
                    };
                }
                const RenderJobResult r = runRenderJob(render);
                if (r.validationErrors)
                    failRuntime("{} Vulkan validation error(s) while rendering (see the log)", r.validationErrors);
                rec["status"] = "done";
                rec["error"] = nullptr;
                Json outputs = Json::array();
                for (const WrittenFile& f : r.written)
                    outputs.push_back({{"file", f.path.lexically_relative(folder).generic_string()}, {"what", f.what}});
                if (j.capture) {
                    for (const fs::path& f : captured.files)
                        outputs.push_back({{"file", f.lexically_relative(folder).generic_string()},
                                           {"what", "simulated sensor capture (docs/sensor.md)"}});
                    rec["capture"] = {{"exposure_s", captured.exposure_s}, {"auto_exposed", captured.autoExposed}};
                }
                rec["outputs"] = outputs;
                rec["notes"] = r.notes;
                rec["threads"] = r.threads;  // what the pools, OpenEXR and lavapipe were sized by
                Json stages = Json::object();
                for (const auto& [stage, ms] : r.timings.stages())
                    if (std::string(stage) != "total") stages[stage] = ms;  // the record's "job" is the whole job
                stages["job"] = msSince(t0);
                rec["timings_ms"] = stages;
                ++s.rendered;
                ++p.rendered;
                renderSeconds.push_back(msSince(t0) / 1000.0);
                p.line = fmt::format("{}: rendered in {:.2f} s", j.id, msSince(t0) / 1000.0);
            } catch (const std::exception& e) {
                rec["status"] = "failed";
                rec["error"] = e.what();
                rec["outputs"] = Json::array();
                rec["timings_ms"] = {{"job", msSince(t0)}};
                ++s.failed;
                ++p.failed;
                s.failures.push_back(j.id + ": " + e.what());
                p.line = fmt::format("{}: FAILED: {}", j.id, e.what());
            }
            rec["finished"] = utcNow();
            try {
                writeFileAtomically(folder / kRecordFile, rec.dump(2) + "\n");
            } catch (const std::exception& e) {
                // Without a record the job is rendered again next time; the batch goes on.
                const std::string why = fmt::format("its record could not be written: {}", e.what());
                if (rec["status"] == "done") {
                    --s.rendered;
                    --p.rendered;
                    ++s.failed;
                    ++p.failed;
                    s.failures.push_back(fmt::format("{}: {}", j.id, why));
                } else {
                    s.failures.back() += "; and " + why;  // one line per failed job, with both reasons
                }
                p.line = s.failures.back();
            }
        }
        ++p.done;
        p.elapsedSeconds = msSince(start) / 1000.0;
        if (progress) progress(p);
    }
    s.seconds = msSince(start) / 1000.0;
    if (!renderSeconds.empty()) s.renderSecondsMedian = median(renderSeconds);
    s.otherVersions = fmt::format("{}", fmt::join(otherVersions, ", "));
    return s;
}

namespace {

std::string cellText(const Json& v) {
    if (v.is_null()) return "";
    if (v.is_string()) return v.get<std::string>();
    if (v.is_array()) {
        std::vector<std::string> parts;
        for (const Json& e : v) parts.push_back(cellText(e));
        return fmt::format("{}", fmt::join(parts, ";"));
    }
    return v.dump();
}

}  // namespace

IndexedJob indexedJob(const ResolvedJob& j) {
    return {j.position, j.id, j.origin, j.settings, j.axes, j.used};
}

IndexSummary writeBatchIndex(const fs::path& dir, const std::vector<IndexedJob>* sweepJobs) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) failInput(Where{dir.string()}, "not a folder of batch results");
    std::vector<Json> rows;
    std::vector<std::string> columns = {"id", "status", "current", "error", "scene"};
    std::set<std::string> known(columns.begin(), columns.end());
    auto addColumn = [&](const std::string& c) {
        if (known.insert(c).second) columns.push_back(c);
    };
    std::vector<std::string> extra;  // settings, axes and timing columns, in first-seen order
    // A row from what a job renders (a record's, or a sweep job's without one).
    auto settingsRow = [&](Json& row, const Json& settings, const Json& axes, const Json& used) {
        const Json render = settings.value("render", Json::object());
        row["scene"] = settings.value("scene", "");
        for (const Json& o : settings.value("set", Json::array())) {
            const std::string text = o.is_string() ? o.get<std::string>() : "";
            const size_t eq = text.find('=');
            const std::string key = "set:" + text.substr(0, eq);
            row[key] = eq == std::string::npos ? "" : text.substr(eq + 1);
            extra.push_back(key);
        }
        for (const auto& [k, v] : render.items()) {
            row[k] = v.is_array() ? Json(cellText(v)) : v;
            extra.push_back(k);
        }
        // Settings the job left alone: the value it used (a default, the scene's own), not a blank.
        if (used.is_object())
            for (const auto& [k, v] : used.items()) {
                if (!row.contains(k)) row[k] = v;
                extra.push_back(k);
            }
        if (axes.is_object())
            for (const auto& [k, v] : axes.items()) {
                row["axis:" + k] = v.is_array() || v.is_object() ? Json(v.dump()) : v;
                extra.push_back("axis:" + k);
            }
    };
    auto recordRow = [&](const JobRecord& rec) {
        const Json& j = rec.json;
        Json row = Json::object();
        row["id"] = rec.id;
        row["status"] = j["status"];
        row["current"] = true;
        row["error"] = rec.error.empty() ? Json(nullptr) : Json(rec.error);
        // value() returns copies: kept in locals, since items() refers to its object.
        const Json settings = j.value("settings", Json::object());
        const Json timings = j.value("timings_ms", Json::object());
        settingsRow(row, settings, j.value("axes", Json::object()), j.value("used", Json::object()));
        std::vector<std::string> outputs;
        for (const Json& o : j.value("outputs", Json::array()))
            outputs.push_back((fs::path(rec.id) / o.value("file", "")).generic_string());
        row["outputs"] = fmt::format("{}", fmt::join(outputs, ";"));
        for (const auto& [k, v] : timings.items()) {
            row["ms_" + k] = v;
            extra.push_back("ms_" + k);
        }
        row["position"] = j.value("position", 0);
        row["origin"] = j.value("origin", "");
        row["sweep"] = j.value("sweep", "");
        row["host"] = j.value("host", "");
        row["shard"] = j.value("shard", "");
        row["finished"] = j.value("finished", "");
        row["metamer_version"] = j.value("metamer_version", "");
        row["spectra_digest"] = j.value("spectra_digest", "");
        row["digest"] = rec.digest;
        return row;
    };
    std::vector<std::string> unreadable;
    size_t missing = 0, superseded = 0, otherRecords = 0;
    auto readOrNote = [&](const fs::path& folder) {
        const std::optional<JobRecord> rec = readJobRecord(folder);
        // A job.json that is not a record (damaged, of another version, not a file) is said, not
        // silently dropped; the next batch run renders that job again.
        std::error_code e2;
        if (!rec && fs::exists(fs::symlink_status(folder / kRecordFile, e2))) unreadable.push_back(folder.filename().string());
        return rec;
    };
    if (sweepJobs) {
        std::set<std::string> ids;
        for (const IndexedJob& job : *sweepJobs) {
            ids.insert(job.id);
            const std::optional<JobRecord> rec = readOrNote(dir / job.id);
            if (rec && rec->id == job.id) {
                rows.push_back(recordRow(*rec));
                continue;
            }
            // No record: a task that died or has not run yet. Listed, not left out.
            Json row = Json::object();
            row["id"] = job.id;
            row["status"] = "missing";
            row["current"] = true;
            row["error"] = nullptr;
            settingsRow(row, job.settings, job.axes, job.used);
            row["position"] = job.position;
            row["origin"] = job.origin;
            rows.push_back(std::move(row));
            ++missing;
        }
        for (const auto& e : fs::directory_iterator(dir, ec))
            if (e.is_directory() && !ids.count(e.path().filename().string()) && readJobRecord(e.path())) ++otherRecords;
    } else {
        std::vector<fs::path> folders;
        for (const auto& e : fs::directory_iterator(dir, ec))
            if (e.is_directory()) folders.push_back(e.path());
        std::sort(folders.begin(), folders.end());
        for (const fs::path& folder : folders)
            if (const std::optional<JobRecord> rec = readOrNote(folder)) rows.push_back(recordRow(*rec));
        // The latest record of each sweep position is current; an earlier one (the sweep or a
        // file it reads was edited since, so the job got a new id) is superseded.
        std::map<std::pair<std::string, size_t>, std::string> latest;
        for (const Json& r : rows) {
            std::string& f = latest[{r["sweep"].get<std::string>(), r["position"].get<size_t>()}];
            f = std::max(f, r["finished"].get<std::string>());
        }
        for (Json& r : rows)
            if (r["finished"].get<std::string>() < latest[{r["sweep"].get<std::string>(), r["position"].get<size_t>()}]) {
                r["current"] = false;
                ++superseded;
            }
    }
    for (const std::string& k : extra) addColumn(k);
    for (const char* c : {"outputs", "position", "origin", "sweep", "host", "shard", "finished", "metamer_version", "spectra_digest",
                          "digest"})
        addColumn(c);
    std::stable_sort(rows.begin(), rows.end(),
                     [](const Json& a, const Json& b) { return a["position"].get<size_t>() < b["position"].get<size_t>(); });
    IndexSummary s;
    s.unreadable = unreadable;
    s.records = rows.size() - missing;
    s.missing = missing;
    s.superseded = superseded;
    s.otherRecords = otherRecords;
    std::string csv;
    for (size_t c = 0; c < columns.size(); ++c) csv += (c ? "," : "") + csvQuoted(columns[c]);
    csv += "\n";
    Json json = Json::array();
    for (const Json& row : rows) {
        Json flat = Json::object();
        for (size_t c = 0; c < columns.size(); ++c) {
            const Json v = row.contains(columns[c]) ? row[columns[c]] : Json(nullptr);
            csv += (c ? "," : "") + csvQuoted(cellText(v));
            flat[columns[c]] = v;
        }
        csv += "\n";
        json.push_back(flat);
        if (row["status"] == "done") ++s.done;
        if (row["status"] == "failed") ++s.failed;
    }
    s.csv = dir / "index.csv";
    s.json = dir / "index.json";
    // Under the dataset's claim (DIR/.claim; another run's index takes milliseconds, so it is
    // waited for, up to 10 s) no other process writes the index, so the temporaries a killed run
    // left (.index.csv.tmp-…) are stale and removed. Without the claim the index is still written
    // (atomically) and the temporaries are left for the next run.
    std::optional<JobClaim> claim;
    std::string heldBy;
    for (int i = 0; i < 100 && !(claim = JobClaim::tryClaim(dir, false, heldBy)); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (claim)
        for (const auto& e : fs::directory_iterator(dir, ec)) {
            const std::string name = e.path().filename().string();
            if (name.rfind(".index.csv.tmp-", 0) == 0 || name.rfind(".index.json.tmp-", 0) == 0) fs::remove(e.path(), ec);
        }
    writeFileAtomically(s.csv, csv);
    writeFileAtomically(s.json, json.dump(2) + "\n");
    return s;
}

}  // namespace metamer
