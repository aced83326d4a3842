#include "app/batch_command.h"

#include "app/cli_checks.h"
#include "app/render_flags.h"

#include "batch/batch.h"
#include "batch/slurm_script.h"
#include "core/error.h"
#include "render/render_job.h"
#include "render/render_setup.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <set>

namespace fs = std::filesystem;

namespace metamer {

namespace {

// A sweep of thousands of jobs repeats the same warning (a spectrum that does not cover the grid)
// for every job: each distinct warning is printed once.
void warnOnce(const std::string& line) {
    static std::mutex m;
    static std::set<std::string> seen;
    std::lock_guard<std::mutex> lock(m);
    if (seen.insert(line).second) std::fprintf(stderr, "%s\n", line.c_str());
}

fs::path outFolder(const BatchArgs& a, const Sweep& sweep) {
    if (!a.out.empty()) return a.out;
    if (!sweep.out.empty()) return sweep.out;
    return fs::path("out") / fs::path(a.sweep).stem();
}

std::string duration(double seconds) {
    if (seconds < 120) return fmt::format("{:.0f} s", seconds);
    if (seconds < 7200) return fmt::format("{:.0f} min", seconds / 60);
    return fmt::format("{:.1f} h", seconds / 3600);
}

void printIndexSummary(const IndexSummary& s, bool counts) {
    for (const std::string& id : s.unreadable)
        std::printf("note: %s/job.json is not a job record (damaged, or not written by this version); left out of "
                    "the index, and rendered again by the next batch run\n",
                    id.c_str());
    if (s.otherRecords)
        std::printf("note: %zu records of jobs that are not this sweep's (an earlier version of it) are left out\n",
                    s.otherRecords);
    if (s.superseded)
        std::printf("note: %zu records are superseded by a later one at the same sweep position (column current = "
                    "false)\n",
                    s.superseded);
    if (counts)
        std::printf("index: %zu job records (%zu done, %zu failed)%s → %s, %s\n", s.records, s.done, s.failed,
                    s.missing ? fmt::format(", {} jobs without a record (status missing)", s.missing).c_str() : "",
                    s.csv.c_str(), s.json.c_str());
    else
        std::printf("index: %zu job records → %s, %s\n", s.records, s.csv.c_str(), s.json.c_str());
}

}  // namespace

CLI::App* addBatchCommand(CLI::App& app, BatchArgs& a) {
    auto* c = app.add_subcommand("batch", "render a sweep of jobs (a dataset), resumable and sharded (docs/batch.md)");
    c->add_option("sweep", a.sweep, "sweep file (.json) or manifest (.jsonl, .csv)");
    c->add_option("--out,-o", a.out, "the dataset's folder (default: the sweep's \"out\", else out/<sweep name>)")->check(outputFolder());
    c->add_flag("--list", a.list, "print the jobs (id, status, origin) without rendering; validates every job");
    c->add_flag("--dry-run", a.dryRun, "validate every job and say what would be rendered; renders nothing");
    c->add_option("--shard", a.shard,
                  "render shard I of N (0 ≤ I < N; default: SLURM_ARRAY_TASK_ID of SLURM_ARRAY_TASK_COUNT, else all)");
    c->add_flag("--retry-failed", a.retryFailed, "render again the jobs whose record says they failed");
    c->add_flag("--break-claims", a.breakClaims,
                "take over jobs claimed by another run (another host's run that is gone: a crashed node)");
    c->add_option("--index", a.index,
                  "gather the job records under DIR into DIR/index.csv and index.json (with a sweep: exactly its jobs, "
                  "those without a record as missing)");
    addRenderFlag(c, "validation", a.validation);
    addRenderFlag(c, "device", a.device);
    c->add_flag("--quiet,-q", a.quiet, "no progress output");
    c->add_flag("--slurm", a.slurm,
                "validate every job, then write DIR/slurm/{array.sbatch,index.sbatch,submit.sh}: a Slurm job array of "
                "--tasks shards and the index after it; renders nothing");
    c->add_option("--tasks", a.tasks, "--slurm: array tasks (shards)")->check(CLI::Range(1, 100000))->capture_default_str();
    c->add_option("--array-limit", a.arrayLimit, "--slurm: at most K tasks at once (sbatch --array=...%K)")
        ->check(CLI::Range(1, 100000));
    c->add_option("--partition", a.partition, "--slurm: the partition (sbatch -p)");
    c->add_option("--time", a.time, "--slurm: time limit per task (sbatch -t), e.g. 02:00:00");
    c->add_option("--cpus-per-task", a.cpusPerTask, "--slurm: CPUs per task (sbatch -c)")->check(CLI::Range(1, 1024));
    c->add_option("--mem", a.mem, "--slurm: memory per task (sbatch --mem), e.g. 8G");
    c->add_option("--sbatch", a.sbatchOptions,
                  "--slurm: any other sbatch option for every task, repeatable: --sbatch gres=gpu:1 (or "
                  "--sbatch=--gres=gpu:1), --sbatch account=lab, --sbatch qos=long");
    return c;
}

int runBatchCommand(const BatchArgs& a) {
    if (!a.index.empty()) {
        // With a sweep: exactly its jobs (each resolved for its id), those without a record as
        // missing. Without: every record, the superseded ones marked.
        std::vector<IndexedJob> jobs;
        if (!a.sweep.empty()) {
            const Sweep sweep = readSweep(a.sweep);
            for (size_t p = 0; p < sweep.size(); ++p) jobs.push_back(indexedJob(resolveJob(sweep, p, a.index)));
        }
        const IndexSummary s = writeBatchIndex(a.index, a.sweep.empty() ? nullptr : &jobs);
        printIndexSummary(s, true);
        return 0;
    }
    if (a.sweep.empty()) failInput(Where{"", "sweep"}, "give a sweep file (or --index DIR)");
    setWarningSink(warnOnce);
    const Sweep sweep = readSweep(a.sweep);
    const auto [shard, shards] = parseShard(a.shard);
    BatchOptions o;
    o.out = outFolder(a, sweep);
    o.shard = shard;
    o.shards = shards;
    o.retryFailed = a.retryFailed;
    o.breakClaims = a.breakClaims;
    o.validation = a.validation;
    o.device = a.device;
    const std::vector<size_t> positions = shardPositions(sweep.size(), shard, shards);

    if (a.slurm) {
        if (!a.shard.empty()) failInput(Where{"", "--shard"}, "--slurm writes every shard's task; give no --shard");
        SlurmOptions so;
        so.tasks = int(std::min<size_t>(size_t(a.tasks), sweep.size()));  // no task without a job
        so.arrayLimit = a.arrayLimit;
        so.partition = a.partition;
        so.time = a.time;
        so.cpusPerTask = a.cpusPerTask;
        so.mem = a.mem;
        so.metamer = fs::read_symlink("/proc/self/exe");
        so.sweep = fs::absolute(a.sweep);
        so.out = fs::absolute(o.out);
        if (a.retryFailed) so.extraArgs.push_back("--retry-failed");
        if (a.validation) so.extraArgs.push_back("--validation");
        if (!a.device.empty()) so.extraArgs.insert(so.extraArgs.end(), {"--device", a.device});
        so.sbatchOptions = a.sbatchOptions;
        // What changes a job's ids goes into the scripts, not left to sbatch's --export=ALL.
        for (const char* v : {"METAMER_SPECTRA", "METAMER_DEVICE"})
            if (const char* value = std::getenv(v)) so.environment.push_back({v, value});
        checkSlurmOptions(so);
        // Every job checked here, before anything is submitted.
        for (size_t p = 0; p < sweep.size(); ++p) resolveJob(sweep, p, o.out);
        const SlurmScripts scripts = writeSlurmScripts(so);
        std::printf("%s: %zu jobs, all valid, in %d array tasks (%zu jobs each at most)\n", a.sweep.c_str(),
                    sweep.size(), so.tasks, (sweep.size() + size_t(so.tasks) - 1) / size_t(so.tasks));
        std::printf("wrote %s (the array), %s (the index), %s\n", scripts.array.c_str(), scripts.index.c_str(),
                    scripts.submit.c_str());
        std::printf("submit with: sh %s   (again to resume; logs in %s)\n", scripts.submit.c_str(),
                    scripts.logs.c_str());
        return 0;
    }

    if (a.list || a.dryRun) {
        size_t done = 0, failed = 0, todo = 0;
        for (size_t p : positions) {
            const ResolvedJob j = resolveJob(sweep, p, o.out);
            const std::optional<JobRecord> r = readJobRecord(j.render.outDir);
            const bool fresh = !r || r->digest != j.digest;
            const bool isDone = !fresh && r->status == JobStatus::Done;
            const char* status = fresh ? "to render" : isDone ? "done" : "failed";
            (fresh ? todo : isDone ? done : failed)++;
            if (a.list) std::printf("%s\t%s\t%s\n", j.id.c_str(), status, sweep.job(p).origin.c_str());
        }
        std::fprintf(a.list ? stderr : stdout, "%s: %zu jobs%s, all valid: %zu done, %zu failed, %zu to render, in %s\n",
                     a.sweep.c_str(), positions.size(),
                     shards > 1 ? fmt::format(" in shard {}/{}", shard, shards).c_str() : "", done, failed, todo,
                     o.out.c_str());
        return 0;
    }

    vk::ContextOptions co = vk::contextOptionsFromEnvironment();
    co.validation = co.validation || a.validation;
    if (!a.device.empty()) {
        co.device = a.device;
        co.deviceFrom = "--device";
    }
    vk::Context ctx(co);
    const bool terminal = ::isatty(STDERR_FILENO);
    auto progress = [&](const BatchProgress& p) {
        if (a.quiet) return;
        const double rate = p.elapsedSeconds > 0 ? p.done / p.elapsedSeconds : 0;
        const std::string eta = rate > 0 ? duration((p.total - p.done) / rate) : "?";
        if (terminal)
            std::fprintf(stderr, "\r\033[K[%zu/%zu] %zu rendered, %zu skipped, %zu failed%s; %.1f jobs/s, ETA %s",
                         p.done, p.total, p.rendered, p.skipped, p.failed,
                         p.held ? fmt::format(", {} held by other runs", p.held).c_str() : "", rate, eta.c_str());
        else
            std::fprintf(stderr, "[%zu/%zu] %s\n", p.done, p.total, p.line.c_str());
        std::fflush(stderr);
    };
    const BatchSummary s = runBatch(sweep, o, ctx, progress);
    if (terminal && !a.quiet) std::fprintf(stderr, "\n");
    std::printf("%s: %zu jobs%s: %zu rendered, %zu skipped (done before), %zu failed, in %.1f s (median %.3f s a "
                "rendered job) → %s\n",
                a.sweep.c_str(), s.jobs, shards > 1 ? fmt::format(" in shard {}/{}", shard, shards).c_str() : "",
                s.rendered, s.skipped, s.failed, s.seconds, s.renderSecondsMedian, o.out.c_str());
    for (const std::string& f : s.failures) std::printf("failed: %s\n", f.c_str());
    for (const std::string& h : s.heldBy) std::printf("held: %s (left to that run)\n", h.c_str());
    if (s.held)
        std::printf("%zu job(s) claimed by other runs were left to them; run again when they end (or with "
                    "--break-claims if a run on another host is gone)\n",
                    s.held);
    if (s.otherVersion)
        std::printf("note: %zu of the skipped jobs were rendered by Metamer %s (this is %s): same scene, settings and "
                    "input files, but the renderer differs; remove their folders to render them again\n",
                    s.otherVersion, s.otherVersions.c_str(), metamerVersion());
    if (shards == 1 && s.jobs > 0) printIndexSummary(writeBatchIndex(o.out, &s.indexed), false);
    return s.failed ? int(ExitCode::Failure) : 0;
}

}  // namespace metamer
