// The Slurm job array of a sweep: an sbatch script whose every task renders one shard (the shard
// comes from SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT, batch/batch.h), a second script that
// gathers the index, and submit.sh, which submits the array and then the index as a job that runs
// after every task has ended (afterany: also when some failed or were cancelled). Plain sbatch
// options only, so the scripts run unchanged on a university cluster. docs/batch.md, "Slurm".
// Tests: tests/slurm_test.sh (a real single-node Slurm).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace metamer {

struct SlurmOptions {
    int tasks = 4;             // array tasks = shards
    int arrayLimit = 0;        // at most this many tasks at once (%K); 0: no limit
    std::string partition;     // -p; empty: the cluster's default
    std::string time;          // -t per task, e.g. "02:00:00"; empty: the partition's default
    int cpusPerTask = 0;       // -c; 0: Slurm's default
    std::string mem;           // --mem per task, e.g. "8G"; empty: the default
    std::string jobName;       // -J; empty: metamer-<the sweep's name>, other characters as '_' 
    std::filesystem::path metamer;  // the metamer binary, absolute
    std::filesystem::path sweep;    // the sweep file, absolute
    std::filesystem::path out;      // the dataset folder, absolute
    std::vector<std::string> extraArgs;  // passed to every task's metamer batch (--retry-failed, …)
    // Any other sbatch option, as "--gres=gpu:1" or "gres=gpu:1" (checked: checkSlurmOptions).
    std::vector<std::string> sbatchOptions;
    // Variables that change what a job renders (METAMER_SPECTRA, METAMER_DEVICE), exported by the
    // task script itself rather than left to sbatch's --export=ALL.
    std::vector<std::pair<std::string, std::string>> environment;
};

struct SlurmScripts {
    std::filesystem::path array, index, submit, logs;
};

// Input errors for values Slurm would not accept as they are, before anything is written: the
// partition, time, memory and job name against sbatch(1)'s syntax, `out` (the logs go on #SBATCH
// --output lines) without whitespace, control characters, quotes, backslashes or '%', and each
// passed-through sbatch option as --NAME[=VALUE] with no whitespace, quotes or control characters,
// not one the scripts set themselves (--array, --output, …: those have their own flags).
// Values that reach a shell line (the binary, the sweep, the folder) are quoted (shellQuote).
void checkSlurmOptions(const SlurmOptions& options);

// Writes out/slurm/{array.sbatch, index.sbatch, submit.sh} (atomically) and creates out/slurm/logs.
SlurmScripts writeSlurmScripts(const SlurmOptions& options);

// `text` quoted for a POSIX shell: '...' with every ' written as '\''.
std::string shellQuote(const std::string& text);

}  // namespace metamer
