// How many threads this process should run: the one number every thread pool, OpenEXR's thread
// count and lavapipe's LP_NUM_THREADS are sized by, so that a render given 4 CPUs by Slurm or by
// `taskset` uses 4, not the machine's 128 (std::thread::hardware_concurrency counts the machine).
// In order: --threads (setThreadCount); SLURM_CPUS_PER_TASK, at most the CPUs this process may
// run on; else the CPUs this process may run on (sched_getaffinity: taskset, cgroups' cpusets,
// srun's binding). docs/cli.md, "Threads". Tests: engine/core/cpu_count_test.cpp, tests/cli_test.cpp
// (CliThreads.*).
#pragma once

#include <optional>
#include <string>

namespace metamer {

struct CpuCount {
    int threads = 1;
    std::string source;  // why this many, for -v and records: "sched_getaffinity (1 of 2 CPUs)"
};

// The most threads asked for: more fail in thread creation (99 999 did, naming nothing), and no
// pool here gains past a machine's cores.
constexpr int kMaxThreads = 1024;

// The rule above as a pure function: `flag` is --threads, `slurmCpusPerTask` the variable's text
// (null: unset), `affinityCpus` the CPUs the process may run on. A value that is not a whole
// number from 1 to kMaxThreads is an input error naming --threads or SLURM_CPUS_PER_TASK.
CpuCount chooseCpuCount(std::optional<int> flag, const char* slurmCpusPerTask, int affinityCpus);

// The CPUs this process may run on (sched_getaffinity), at least 1.
int affinityCpuCount();

// Fixes the count for the rest of the process from --threads (nullopt: from the environment).
// Call it before the first thread pool, the first EXR and the first Vulkan instance: those read
// the count once. Throws the input errors of chooseCpuCount.
void setThreadCount(std::optional<int> flag);

// The count (from the environment on first use, when setThreadCount was not called).
const CpuCount& cpuCount();
int usableCpuCount();

}  // namespace metamer
