// Running the `metamer` tool from a test, as a user would: one helper for every CLI-level test
// (tests/cli_test.cpp, tests/bad_inputs_test.cpp, engine/compare/compare_cli_test.cpp,
// engine/bench/bench_cli_test.cpp).
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace metamer::test {

struct CliRun {
    int code = -1;       // the exit status; a signal shows as 128 + signal, a timeout as 124
    std::string output;  // stdout and stderr together, or stderr alone (CliOptions::stderrOnly)
};

struct CliOptions {
    std::string env;          // prefixed to the command: "METAMER_DEVICE=x"
    std::string dir;          // run in this folder (messages then name files as given)
    int timeoutSeconds = 0;   // > 0: killed after this long (a hung case fails instead of hanging)
    bool stderrOnly = false;  // capture stderr only (stdout discarded)
};

// `metamer ARGS` through the shell.
inline CliRun runMetamer(const std::string& args, const CliOptions& o = {}) {
    std::string cmd;
    if (!o.dir.empty()) cmd += "cd '" + o.dir + "' && ";
    cmd += o.env + " ";
    if (o.timeoutSeconds > 0) cmd += "timeout " + std::to_string(o.timeoutSeconds) + " ";
    cmd += METAMER_BINARY " " + args + (o.stderrOnly ? " 2>&1 >/dev/null" : " 2>&1");
    CliRun r;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    char buf[4096];
    while (size_t n = fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
    const int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    return r;
}

}  // namespace metamer::test
