#include "batch/slurm_script.h"

#include "core/error.h"
#include "io/atomic_file.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cctype>
#include <regex>


namespace fs = std::filesystem;

namespace metamer {

namespace {

// Executable by everyone who may read it (sbatch does not need it; a user running submit.sh does).
void writeScript(const fs::path& path, const std::string& text) {
    writeFileAtomically(path, text);
    fs::permissions(path, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec | fs::perms::others_read |
                              fs::perms::others_exec);
}

std::string header(const SlurmOptions& o, const std::string& name, const std::string& log) {
    std::string h = "#!/bin/bash\n";
    h += fmt::format("#SBATCH --job-name={}\n", name);
    h += fmt::format("#SBATCH --output={}\n", log);
    if (!o.partition.empty()) h += fmt::format("#SBATCH --partition={}\n", o.partition);
    if (!o.time.empty()) h += fmt::format("#SBATCH --time={}\n", o.time);
    if (!o.mem.empty()) h += fmt::format("#SBATCH --mem={}\n", o.mem);
    for (const std::string& opt : o.sbatchOptions) h += fmt::format("#SBATCH {}{}\n", opt.rfind("--", 0) == 0 ? "" : "--", opt);
    return h;
}

// The variables that change what a job renders, as they were when the scripts were written.
std::string exports(const SlurmOptions& o) {
    std::string e;
    for (const auto& [k, v] : o.environment) e += fmt::format("export {}={}\n", k, shellQuote(v));
    return e;
}

// Each value that reaches an #SBATCH line must be exactly what Slurm accepts for that option: a
// newline there would end sbatch's directive parsing (losing --array) and run the rest as a shell
// command, a space would add an option. So each is matched against Slurm's own syntax (sbatch(1)).
void checkValue(const std::string& value, const char* option, const std::regex& syntax, const char* expected) {
    if (!value.empty() && !std::regex_match(value, syntax))
        failInput(Where{"", option}, "expected {}, got '{}'", expected, value);
}

// A path on an #SBATCH --output line: whitespace or a quote would split or open the option, a '%'
// is one of Slurm's filename patterns (%j, %A, …) and a backslash turns them all off.
void checkSbatchPath(const fs::path& path, const char* option) {
    for (const unsigned char c : path.string())
        if (c < 0x21 || c == 0x7f || c == '%' || c == '"' || c == '\'' || c == '\\')
            failInput(Where{"", option},
                      "'{}' cannot go on an #SBATCH line (its log files are --output={}/slurm/logs/…): a path without "
                      "whitespace, control characters, quotes, backslashes or '%' is needed for --slurm",
                      path.string(), path.string());
}

// The job name from the sweep's name, in the characters every Slurm tool prints unquoted.
std::string jobNameFrom(const std::string& stem) {
    std::string name = "metamer-";
    for (const char c : stem.substr(0, 64)) name += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' ? c : '_';
    return name;
}

}  // namespace

void checkSlurmOptions(const SlurmOptions& o) {
    if (o.tasks < 1) failInput(Where{"", "--tasks"}, "expected at least 1 array task, got {}", o.tasks);
    if (o.arrayLimit < 0) failInput(Where{"", "--array-limit"}, "expected a positive limit, got {}", o.arrayLimit);
    static const std::regex partition("[A-Za-z0-9_.-]+(,[A-Za-z0-9_.-]+)*");
    static const std::regex time("[0-9]+(:[0-9]+){0,2}|[0-9]+-[0-9]+(:[0-9]+){0,2}|UNLIMITED|INFINITE");
    static const std::regex mem("[0-9]+[KMGTkmgt]?");
    static const std::regex name("[A-Za-z0-9_.-]+");
    checkValue(o.partition, "--partition", partition,
               "a partition name (letters, digits, '_', '.', '-'; several joined by commas)");
    checkValue(o.time, "--time", time,
               "a time limit as Slurm writes one: MINUTES, MINUTES:SECONDS, HOURS:MINUTES:SECONDS, DAYS-HOURS, "
               "DAYS-HOURS:MINUTES, DAYS-HOURS:MINUTES:SECONDS or UNLIMITED");
    checkValue(o.mem, "--mem", mem, "a memory size: digits and an optional unit K, M, G or T (e.g. 8G)");
    checkValue(o.jobName, "--job-name", name, "a job name (letters, digits, '_', '.', '-')");
    checkSbatchPath(o.out, "--out");
    // The sweep and the binary go on the scripts' exec lines, shell-quoted; a control character
    // there (a newline in the sweep's name) would still split the line for whoever reads or edits
    // the script, and Slurm's own tools print job commands unquoted.
    for (const auto& [path, what] : {std::pair{o.sweep, "the sweep file"}, std::pair{o.metamer, "the metamer binary"}})
        for (const unsigned char c : path.string())
            if (c < 0x20 || c == 0x7f)
                failInput(Where{path.string()},
                          "{}'s path holds a control character, which cannot go on the task script's exec line: rename "
                          "it for --slurm",
                          what);
    static const std::regex option("--[a-z][a-z-]*(=[A-Za-z0-9_.,:=/@+%*-]+)?");
    static const std::vector<std::pair<std::string, std::string>> ours = {
        {"--array", "--tasks and --array-limit"}, {"--output", "the logs' folder under --out"},
        {"--error", "the logs' folder under --out"}, {"--job-name", "the sweep's name"},
        {"--partition", "--partition"}, {"--time", "--time"}, {"--mem", "--mem"},
        {"--cpus-per-task", "--cpus-per-task"}, {"--wrap", "the task script"}, {"--parsable", "submit.sh"},
        {"--dependency", "submit.sh (the index runs after the array)"}};
    for (const std::string& raw : o.sbatchOptions) {
        const std::string opt = raw.rfind("--", 0) == 0 ? raw : "--" + raw;
        if (!std::regex_match(opt, option))
            failInput(Where{"", "--sbatch"},
                      "expected an sbatch option as --NAME or --NAME=VALUE (e.g. --gres=gpu:1, --account=lab), with no "
                      "whitespace, quotes or control characters; got '{}'",
                      raw);
        const std::string optName = opt.substr(0, opt.find('='));
        for (const auto& [n, by] : ours)
            if (optName == n) failInput(Where{"", "--sbatch"}, "'{}' is set by the scripts themselves (from {})", raw, by);
    }
    static const std::regex variable("[A-Z_][A-Z0-9_]*");
    for (const auto& [k, v] : o.environment)
        if (!std::regex_match(k, variable) || v.find('\0') != std::string::npos)
            failInput(Where{"", k}, "cannot be written into the task script");
}

namespace {

// The renderer's --threads: the CPUs Slurm gave the task (SLURM_CPUS_PER_TASK, set when the job
// declares --cpus-per-task; sbatch -c on the command line overrides the script's), else the count
// declared here; without either, no flag, and metamer counts the CPUs it is bound to
// (core/cpu_count.h).
std::string threadsArgument(const SlurmOptions& o) {
    if (o.cpusPerTask) return fmt::format("--threads \"${{SLURM_CPUS_PER_TASK:-{}}}\"", o.cpusPerTask);
    return "${SLURM_CPUS_PER_TASK:+--threads \"$SLURM_CPUS_PER_TASK\"}";
}

}  // namespace

std::string shellQuote(const std::string& text) {
    std::string q = "'";
    for (char c : text) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

SlurmScripts writeSlurmScripts(const SlurmOptions& o) {
    checkSlurmOptions(o);  // before anything is written
    const fs::path dir = o.out / "slurm";
    SlurmScripts s{dir / "array.sbatch", dir / "index.sbatch", dir / "submit.sh", dir / "logs"};
    std::error_code ec;
    fs::create_directories(s.logs, ec);
    if (ec) failRuntime("cannot create {}: {}", s.logs.string(), ec.message());
    const std::string name = o.jobName.empty() ? jobNameFrom(o.sweep.stem().string()) : o.jobName;
    std::vector<std::string> extra;
    for (const std::string& a : o.extraArgs) extra.push_back(shellQuote(a));
    const std::string extraText = extra.empty() ? "" : " " + fmt::format("{}", fmt::join(extra, " "));

    std::string array = header(o, name, (s.logs / "task-%A_%a.log").string());
    array += fmt::format("#SBATCH --array=0-{}{}\n", o.tasks - 1, o.arrayLimit ? fmt::format("%{}", o.arrayLimit) : "");
    if (o.cpusPerTask) array += fmt::format("#SBATCH --cpus-per-task={}\n", o.cpusPerTask);
    array += fmt::format(
        "# Written by metamer batch --slurm (docs/batch.md). Each task renders the shard\n"
        "# SLURM_ARRAY_TASK_ID of SLURM_ARRAY_TASK_COUNT; a resubmission skips what is done.\n"
        "set -euo pipefail\n"
        "{}"
        "echo \"metamer batch: array task $SLURM_ARRAY_TASK_ID of $SLURM_ARRAY_TASK_COUNT on $(hostname)\"\n"
        "exec {} batch {} --out {} {}{}\n",
        exports(o), shellQuote(o.metamer.string()), shellQuote(o.sweep.string()), shellQuote(o.out.string()),
        threadsArgument(o), extraText);
    std::string index = header(o, name + "-index", (s.logs / "index-%j.log").string());
    index += fmt::format(
        "# Written by metamer batch --slurm: the dataset index from every task's records.\n"
        "set -euo pipefail\n"
        "{}"
        "exec {} batch --index {}\n",
        exports(o), shellQuote(o.metamer.string()), shellQuote(o.out.string()));
    std::string submit = fmt::format(
        "#!/bin/sh\n"
        "# Written by metamer batch --slurm (docs/batch.md): submits the array, then the index to run\n"
        "# after every task has ended. Prints the two job ids. Run it again to resume.\n"
        "set -eu\n"
        "array=$(sbatch --parsable {})\n"
        "array=${{array%%;*}}\n"
        "index=$(sbatch --parsable --dependency=afterany:\"$array\" {})\n"
        "echo \"array $array index ${{index%%;*}}\"\n",
        shellQuote(s.array.string()), shellQuote(s.index.string()));
    writeScript(s.array, array);
    writeScript(s.index, index);
    writeScript(s.submit, submit);
    return s;
}

}  // namespace metamer
