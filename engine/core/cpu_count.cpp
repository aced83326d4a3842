#include "core/cpu_count.h"

#include "core/error.h"

#include <sched.h>

#include <cstdlib>
#include <mutex>

namespace metamer {

namespace {

std::mutex gMutex;
std::optional<CpuCount> gCount;

// A whole number ≥ 1, or an input error at `where`.
int positiveCount(const std::string& text, const Where& where) {
    char* end = nullptr;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || end == text.c_str() || *end != '\0' || v < 1 || v > kMaxThreads)
        failInput(where, "'{}' is not a thread count; expected a whole number from 1 to {}", text, kMaxThreads);
    return int(v);
}

std::string cpus(int n) { return fmt::format("{} CPU{}", n, n == 1 ? "" : "s"); }

}  // namespace

CpuCount chooseCpuCount(std::optional<int> flag, const char* slurmCpusPerTask, int affinityCpus) {
    if (affinityCpus < 1) affinityCpus = 1;
    if (flag) {
        if (*flag < 1 || *flag > kMaxThreads)
            failInput(Where{"", "--threads"}, "'{}' is not a thread count; expected a whole number from 1 to {}", *flag,
                      kMaxThreads);
        return {*flag, "--threads"};
    }
    if (slurmCpusPerTask && *slurmCpusPerTask) {
        const int slurm = positiveCount(slurmCpusPerTask, Where{"", "SLURM_CPUS_PER_TASK"});
        // Slurm's count is what the job asked for; the affinity mask is what it got on this node
        // (the smaller wins: a task bound to fewer CPUs than it declared would oversubscribe them).
        if (slurm <= affinityCpus) return {slurm, "SLURM_CPUS_PER_TASK"};
        return {affinityCpus, fmt::format("SLURM_CPUS_PER_TASK={}, bounded by sched_getaffinity ({})", slurm,
                                          cpus(affinityCpus))};
    }
    return {affinityCpus, fmt::format("sched_getaffinity ({} this process may run on)", cpus(affinityCpus))};
}

int affinityCpuCount() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) != 0) return 1;
    return std::max(1, CPU_COUNT(&set));
}

void setThreadCount(std::optional<int> flag) {
    CpuCount c = chooseCpuCount(flag, std::getenv("SLURM_CPUS_PER_TASK"), affinityCpuCount());
    std::lock_guard<std::mutex> lock(gMutex);
    gCount = std::move(c);
}

const CpuCount& cpuCount() {
    {
        std::lock_guard<std::mutex> lock(gMutex);
        if (gCount) return *gCount;
    }
    setThreadCount(std::nullopt);
    std::lock_guard<std::mutex> lock(gMutex);
    return *gCount;
}

int usableCpuCount() { return cpuCount().threads; }

}  // namespace metamer
