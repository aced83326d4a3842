// The Slurm scripts of `metamer batch --slurm` (batch/slurm_script): their exact text, and every
// value that would reach an #SBATCH line refused unless it is what Slurm accepts there (issue 30,
// class 4: a newline in --partition used to put a shell command into array.sbatch). A real Slurm
// runs the scripts in tests/slurm_test.sh.
#include "batch/slurm_script.h"

#include "core/error.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <unistd.h>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / fmt::format("metamer-slurm-test-{}", ::getpid()) / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::string textOf(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

SlurmOptions options(const fs::path& out) {
    SlurmOptions o;
    o.tasks = 3;
    o.arrayLimit = 2;
    o.partition = "gpu,cpu";
    o.time = "1-02:30:00";
    o.cpusPerTask = 4;
    o.mem = "8G";
    o.metamer = "/opt/metamer/bin/metamer";
    o.sweep = "/data/it's a sweep.json";
    o.out = out;
    o.extraArgs = {"--retry-failed"};
    o.sbatchOptions = {"gres=gpu:1", "--account=lab"};
    o.environment = {{"METAMER_SPECTRA", "/data/my spectra"}};
    return o;
}

}  // namespace

TEST(SlurmScript, TheScriptsAreExactlyTheseLines) {
    const fs::path out = scratch("exact");
    const SlurmScripts s = writeSlurmScripts(options(out));
    const std::string logs = (out / "slurm" / "logs").string();
    EXPECT_EQ(textOf(s.array),
              "#!/bin/bash\n"
              "#SBATCH --job-name=metamer-it_s_a_sweep\n"
              "#SBATCH --output=" + logs + "/task-%A_%a.log\n"
              "#SBATCH --partition=gpu,cpu\n"
              "#SBATCH --time=1-02:30:00\n"
              "#SBATCH --mem=8G\n"
              "#SBATCH --gres=gpu:1\n"
              "#SBATCH --account=lab\n"
              "#SBATCH --array=0-2%2\n"
              "#SBATCH --cpus-per-task=4\n"
              "# Written by metamer batch --slurm (docs/batch.md). Each task renders the shard\n"
              "# SLURM_ARRAY_TASK_ID of SLURM_ARRAY_TASK_COUNT; a resubmission skips what is done.\n"
              "set -euo pipefail\n"
              "export METAMER_SPECTRA='/data/my spectra'\n"
              "echo \"metamer batch: array task $SLURM_ARRAY_TASK_ID of $SLURM_ARRAY_TASK_COUNT on $(hostname)\"\n"
              "exec '/opt/metamer/bin/metamer' batch '/data/it'\\''s a sweep.json' --out '" + out.string() +
                  "' --threads \"${SLURM_CPUS_PER_TASK:-4}\" '--retry-failed'\n");
    EXPECT_EQ(textOf(s.index),
              "#!/bin/bash\n"
              "#SBATCH --job-name=metamer-it_s_a_sweep-index\n"
              "#SBATCH --output=" + logs + "/index-%j.log\n"
              "#SBATCH --partition=gpu,cpu\n"
              "#SBATCH --time=1-02:30:00\n"
              "#SBATCH --mem=8G\n"
              "#SBATCH --gres=gpu:1\n"
              "#SBATCH --account=lab\n"
              "# Written by metamer batch --slurm: the dataset index from every task's records.\n"
              "set -euo pipefail\n"
              "export METAMER_SPECTRA='/data/my spectra'\n"
              "exec '/opt/metamer/bin/metamer' batch --index '" + out.string() + "'\n");
    EXPECT_EQ(textOf(s.submit),
              "#!/bin/sh\n"
              "# Written by metamer batch --slurm (docs/batch.md): submits the array, then the index to run\n"
              "# after every task has ended. Prints the two job ids. Run it again to resume.\n"
              "set -eu\n"
              "array=$(sbatch --parsable '" + s.array.string() + "')\n"
              "array=${array%%;*}\n"
              "index=$(sbatch --parsable --dependency=afterany:\"$array\" '" + s.index.string() + "')\n"
              "echo \"array $array index ${index%%;*}\"\n");
}

TEST(SlurmScript, ValuesSlurmWouldNotTakeAsTheyAreAreRefusedBeforeAnythingIsWritten) {
    const fs::path out = scratch("hostile");
    struct Case {
        const char* option;
        std::function<void(SlurmOptions&)> set;
    };
    const Case cases[] = {
        {"--partition", [](SlurmOptions& o) { o.partition = "debug\necho pwned"; }},
        {"--partition", [](SlurmOptions& o) { o.partition = "debug --account=other"; }},
        {"--partition", [](SlurmOptions& o) { o.partition = "a,,b"; }},
        {"--time", [](SlurmOptions& o) { o.time = "02:00:00\n#SBATCH --array=0-999"; }},
        {"--time", [](SlurmOptions& o) { o.time = "2 hours"; }},
        {"--time", [](SlurmOptions& o) { o.time = "1:2:3:4"; }},
        {"--mem", [](SlurmOptions& o) { o.mem = "8G;rm"; }},
        {"--mem", [](SlurmOptions& o) { o.mem = "8 G"; }},
        {"--mem", [](SlurmOptions& o) { o.mem = "-8G"; }},
        {"--job-name", [](SlurmOptions& o) { o.jobName = "x\ny"; }},
        {"--out", [out](SlurmOptions& o) { o.out = out / "a\nb"; }},
        {"--out", [out](SlurmOptions& o) { o.out = out / "a b"; }},
        {"--out", [out](SlurmOptions& o) { o.out = out / "100%done"; }},
        {"--tasks", [](SlurmOptions& o) { o.tasks = 0; }},
        {"--sbatch", [](SlurmOptions& o) { o.sbatchOptions = {"gres=gpu:1\necho pwned"}; }},
        {"--sbatch", [](SlurmOptions& o) { o.sbatchOptions = {"--account lab"}; }},
        {"--sbatch", [](SlurmOptions& o) { o.sbatchOptions = {"--comment='x'"}; }},
        {"--sbatch", [](SlurmOptions& o) { o.sbatchOptions = {"--array=0-999"}; }},
        {"--sbatch", [](SlurmOptions& o) { o.sbatchOptions = {"output=/tmp/x"}; }},
    };
    for (const Case& c : cases) {
        SlurmOptions o = options(out);
        c.set(o);
        try {
            writeSlurmScripts(o);
            ADD_FAILURE() << c.option << " accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadInput);
            EXPECT_EQ(std::string(e.what()).rfind(std::string(c.option) + ": ", 0), 0u) << e.what();
        }
        EXPECT_FALSE(fs::exists(out / "slurm")) << c.option;
        EXPECT_FALSE(fs::exists(o.out / "slurm")) << c.option;
    }
    // A sweep file whose name holds a newline (issue 51, class 10): it would go on the exec line.
    {
        SlurmOptions o = options(out);
        o.sweep = out / "a\nb.json";
        try {
            writeSlurmScripts(o);
            ADD_FAILURE() << "a newline in the sweep's name accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadInput);
            EXPECT_NE(e.text().find("the sweep file's path holds a control character"), std::string::npos) << e.text();
        }
        EXPECT_FALSE(fs::exists(out / "slurm"));
    }
    // What Slurm does accept passes: each time form, lower-case units, an empty value (the default).
    for (const char* t : {"30", "30:00", "2:30:00", "1-2", "1-2:30", "1-2:30:00", "UNLIMITED", ""}) {
        SlurmOptions o = options(out);
        o.time = t;
        o.mem = "512m";
        EXPECT_NO_THROW(checkSlurmOptions(o)) << t;
    }
}
