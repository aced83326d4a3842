// `metamer batch SWEEP` (render a sweep's jobs, resumable, sharded) and `metamer batch --index DIR`
// (gather a dataset's records into one index). Registered on the main CLI11 app by main.cpp;
// errors are thrown as metamer::Error and mapped to exit codes there. docs/batch.md.
// Tests: tests/batch_test.cpp (the verb as a user runs it).
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace metamer {

struct BatchArgs {
    std::string sweep;
    std::string out;        // --out; empty: the sweep's "out", else out/<sweep stem>
    std::string shard;      // --shard I/N; empty: from SLURM_ARRAY_TASK_ID/COUNT, else 0/1
    std::string index;      // --index DIR: only gather the records under DIR
    bool list = false, dryRun = false, retryFailed = false, validation = false, quiet = false;
    bool breakClaims = false;
    std::vector<std::string> sbatchOptions;
    std::string device;
    // --slurm: write the job array's scripts instead of rendering (batch/slurm_script.h).
    bool slurm = false;
    int tasks = 4, arrayLimit = 0, cpusPerTask = 0;
    std::string partition, time, mem;
};

CLI::App* addBatchCommand(CLI::App& app, BatchArgs& args);

// 0: every job of the shard is done; 1: some job failed (recorded, the others rendered);
// 2 (thrown): the sweep or a job's scene is bad input, and nothing was rendered.
int runBatchCommand(const BatchArgs& args);

}  // namespace metamer
