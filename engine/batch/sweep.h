// A sweep: the list of renders a dataset is made of, read from a sweep file (base scenes or listed
// rows, crossed with axes of scene overrides and render settings) or from a plain manifest (JSONL
// or CSV, one job per line). Each job is a scene, its overrides and its render settings, in the
// order the file gives them; where it came from is kept for error messages. docs/batch.md,
// "The sweep file". Tests: engine/batch/sweep_test.cpp.
#pragma once

#include "batch/sweep_draws.h"
#include "core/error.h"
#include "render/render_job.h"
#include "sensor/capture_files.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace metamer {

// The render settings a sweep may set per job (render_job.h's fields by their CLI names).
const std::vector<std::string>& sweepRenderKeys();

struct SweepJob {
    std::filesystem::path scene;              // as the sweep names it (relative to the sweep's folder)
    std::vector<std::string> overrides;        // KEY=VALUE, applied in order
    nlohmann::ordered_json render = nlohmann::ordered_json::object();  // key → value, sweepRenderKeys()
    std::string origin;  // "rows[2] × axes illuminant=illuminants/A", "line 7": for messages
    nlohmann::ordered_json axes = nlohmann::ordered_json::object();  // axis name → this job's value
    std::optional<size_t> draw;  // the job's draw (0 … draws.count − 1), when the sweep draws
    Where where;         // the sweep file and the row's key or line

    // What the job renders, as one canonical JSON object (sorted render keys, and its draw when it
    // has one): what its id hashes, with the content of the files it reads (batch/batch.h).
    nlohmann::ordered_json settings() const;
};

// An axis of a sweep file: one scene key ("set") or render setting ("render") and its values.
struct SweepAxis {
    std::string name;
    std::string setKey, renderKey;  // exactly one
    std::vector<nlohmann::ordered_json> values;
    Where where;
};

// The most jobs a sweep may have (docs/batch.md): a million job folders is already more than a
// file system lists comfortably, and a product of axes can reach 2⁶⁴ from a few lines.
constexpr size_t kMaxSweepJobs = 1000000;

// A sweep is counted when it is read and its jobs are made one at a time, on demand: a shard
// never builds the jobs of other shards, and a product of axes too large is refused before any
// job exists. Every base (a scene, a row, a manifest line) × the product of the axes × the draws,
// the draws varying fastest, then the last axis.
struct Sweep {
    std::filesystem::path file;    // the sweep or manifest as given
    std::filesystem::path folder;  // the folder its relative paths resolve against
    std::filesystem::path out;     // "out" in the sweep file, resolved; empty when not given

    std::vector<SweepJob> bases;                  // "scenes" and "rows", or the manifest's lines
    std::vector<std::string> common;              // "set": overrides before every job's own
    nlohmann::ordered_json commonRender = nlohmann::ordered_json::object();  // "render"
    std::vector<SweepAxis> axes;
    std::optional<SweepDraws> draws;              // "draws": crossed last, its draws varying fastest

    size_t size() const;                  // the number of jobs
    SweepJob job(size_t position) const;  // job `position` (0-based) of size()
};

// Reads a sweep (.json) or a manifest (.jsonl, .csv). Input errors name the file and the key
// (rows.2.render.detector, axes.1.values) or the line and column. A sweep of more than
// kMaxSweepJobs jobs is refused, naming its axes; so are two jobs that render the same thing
// (same scene, overrides and render settings), naming both — in every mode (--list, --dry-run,
// --slurm, any shard), since under Slurm two tasks would otherwise write one job folder at once.
Sweep readSweep(const std::filesystem::path& file);

// The render job of a sweep job: the scene resolved against the sweep's folder, its overrides,
// settings applied to RenderJob's fields (size "WxH" becomes camera.width/height overrides), the
// outputs in `outDir`. Errors in a value name the job's origin and the key.
RenderJob makeRenderJob(const Sweep& sweep, const SweepJob& job, const std::filesystem::path& outDir);

// The capture a job asks for with its "sensor" setting (and "seed", "frames", "exposure"), if any:
// the sensor resolved (a file against the sweep's folder; a bare name is a library sensor). The
// cube, folder and stem are the batch's to fill in.
std::optional<CaptureRequest> makeCaptureRequest(const Sweep& sweep, const SweepJob& job);

}  // namespace metamer
