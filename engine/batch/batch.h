// metamer batch: a sweep's jobs rendered by one process on one Vulkan device, each into its own
// folder with a record of what it is (job.json), skipped when its record says it is done,
// resumable after any interruption, split into deterministic shards for job arrays, and gathered
// into a dataset index from what is on disk. docs/batch.md. Tests: engine/batch/batch_test.cpp,
// tests/batch_test.cpp.
#pragma once

#include "batch/sweep.h"
#include "vk/context.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace metamer {

// Shard `shard` of `shards` (0 ≤ shard < shards): the jobs at positions k with k mod shards ==
// shard, in order. Balanced (sizes differ by at most one) and disjoint.
std::vector<size_t> shardPositions(size_t jobs, int shard, int shards);

// "I/N" (0-based I), or — when `text` is empty — SLURM_ARRAY_TASK_ID − SLURM_ARRAY_TASK_MIN of
// SLURM_ARRAY_TASK_COUNT from the environment, else 0/1. Errors name --shard or the variable.
std::pair<int, int> parseShard(const std::string& text);

// A job resolved: loaded and checked, its id made from what it renders.
struct ResolvedJob {
    size_t position = 0;   // in the sweep, 0-based
    std::string id;        // <scene stem>-<first 16 hex digits of the digest>: the job's folder name
    std::string digest;    // SHA-256 (hex) of the settings and the content of every file the job reads
    nlohmann::ordered_json settings;  // SweepJob::settings()
    nlohmann::ordered_json used;      // the render settings in effect, set or not (detector, grid, size, …)
    nlohmann::ordered_json axes;      // SweepJob::axes: axis name → value
    std::string origin;               // SweepJob::origin, for the record and the index
    std::vector<std::filesystem::path> inputs;  // the files it reads (scene, spectra, meshes, textures, …)
    RenderJob render;      // outDir = the job's folder
    std::optional<CaptureRequest> capture;  // a simulated sensor's capture after the render (docs/sensor.md)
};

// Loads each job's scene and display plan as the render will (overrides, spectra, paths,
// detector, adaptation, display, grid, mode), without rendering, and derives its id. The first
// job that cannot load is an input error naming the sweep file, the job's row or line, and the
// scene's own file and key.
ResolvedJob resolveJob(const Sweep& sweep, size_t position, const std::filesystem::path& out);

enum class JobStatus { Done, Failed };

struct JobRecord {
    std::string id, digest;
    JobStatus status = JobStatus::Done;
    std::string error;                     // when failed
    nlohmann::ordered_json json;           // the whole record as on disk
};

// The record in `folder`/job.json, if there is a readable one.
std::optional<JobRecord> readJobRecord(const std::filesystem::path& folder);

struct BatchOptions {
    std::filesystem::path out;   // the dataset's folder: one sub-folder per job
    int shard = 0, shards = 1;
    bool retryFailed = false;    // render jobs whose record says they failed (else they are skipped)
    bool validation = false;     // Vulkan validation layers; a validation error fails the job
    bool breakClaims = false;    // take over jobs claimed by other runs (the user says they are gone)
    std::string device;
};

struct BatchProgress {
    size_t done = 0, total = 0;  // jobs of this shard handled so far (rendered, skipped or failed)
    size_t rendered = 0, skipped = 0, failed = 0, held = 0;
    double elapsedSeconds = 0;
    std::string line;            // what happened to the last job, one line
};

// A sweep's job as the index lists it (from ResolvedJob), record or no record.
struct IndexedJob {
    size_t position = 0;
    std::string id, origin;
    nlohmann::ordered_json settings, axes, used;
};
IndexedJob indexedJob(const ResolvedJob& job);

struct BatchSummary {
    size_t jobs = 0, rendered = 0, skipped = 0, failed = 0;
    size_t held = 0;                    // claimed by another live run (batch/job_claim.h): left to it
    double seconds = 0;
    double renderSecondsMedian = 0;  // per rendered job, load to record
    std::vector<std::string> failures;  // "id: error", one per failed job
    std::vector<std::string> heldBy;    // "id: host pid N", one per held job
    std::vector<IndexedJob> indexed;    // this shard's jobs, in order (for writeBatchIndex)
    size_t otherVersion = 0;            // skipped as done, but rendered by another Metamer version
    std::string otherVersions;          // which ("0.0.9, 0.1.0")
};

// Resolves this shard's jobs (all of them before the first render), then renders each one that
// has no record saying it is done (or failed, unless retryFailed) with `context` (one device for
// all), writing its outputs atomically and then its record. A job is claimed first (one writer per
// job, batch/job_claim.h); one claimed by another live run is left to it (`held`). A job that fails
// while rendering is recorded with its error and the batch goes on.
BatchSummary runBatch(const Sweep& sweep, const BatchOptions& options, vk::Context& context,
                      const std::function<void(const BatchProgress&)>& progress = {});

struct IndexSummary {
    size_t records = 0, done = 0, failed = 0;
    size_t missing = 0;          // with a sweep: its jobs without a record (a task that died, not run yet)
    size_t superseded = 0;       // without a sweep: records that are not their job's latest
    size_t otherRecords = 0;     // with a sweep: records of jobs that are not the sweep's (left out)
    std::vector<std::string> unreadable;  // job folders whose job.json is not a record (left out)
    std::filesystem::path csv, json;
};

// The job records under `dir` (dir/*/job.json) gathered into dir/index.csv and dir/index.json
// (written atomically), one row per job: id, status, error, the scene, one column per scene
// override key and render setting (the value the job used where the sweep left it unset), one
// "axis:NAME" column per axis, outputs, timings, where and when it ran, the Metamer version.
// With `sweepJobs` (a sweep's jobs, resolved): exactly those, in order, a job without a record as
// status "missing"; records of other jobs are left out. Without: every record, and a "current"
// column that is false for a record a later one of the same sweep position supersedes (the sweep
// was edited since). Rebuilt from what is on disk each time.
IndexSummary writeBatchIndex(const std::filesystem::path& dir, const std::vector<IndexedJob>* sweepJobs = nullptr);

}  // namespace metamer
