// Atomic file output: write to a temporary file beside the target, then rename it over the target.
// A failed or interrupted write never leaves a half-written file and never harms an existing one.
// Tests: engine/io/atomic_file_test.cpp, engine/io/spectral_exr_test.cpp, tests/interrupted_run_test.cpp,
// tests/cli_test.cpp (CliOutputs).
#pragma once

#include "core/error.h"

#include <filesystem>
#include <string>
#include <vector>

namespace metamer {

class AtomicOutput {
public:
    // Creates the target's folder if missing and an empty temporary file in it, so that a target
    // that cannot work (a folder or a device at the final path, a folder that is not writable, a
    // read-only file system) is found now, before the work, not at commit. Errors name the path.
    // The writer then opens tempPath() itself (truncating it).
    explicit AtomicOutput(std::filesystem::path finalPath);
    ~AtomicOutput();  // removes the temporary file unless committed

    AtomicOutput(const AtomicOutput&) = delete;
    AtomicOutput& operator=(const AtomicOutput&) = delete;

    // Where to write: same folder, hidden, and ending in the final extension so that writers
    // choosing the format by extension (OpenImageIO) pick the right one, e.g.
    // out/.scene.exr.tmp-1234-0.exr for out/scene.exr.
    const std::filesystem::path& tempPath() const { return temp_; }
    const std::filesystem::path& finalPath() const { return final_; }

    // fsyncs the temporary file, renames it over the final path (atomic on POSIX) and fsyncs the
    // folder. Throws a runtime error naming the path if the temporary file is missing or the
    // rename fails; the temporary file is then still removed by the destructor.
    void commit();
    bool committed() const { return committed_; }

    // Runs `write` (the writer's work on tempPath()); an Error from it is thrown again with the
    // temporary file's name replaced by the final one, so that a message from the library (a full
    // disk, say) names the file the user asked for.
    template <typename Write>
    void naming(Write&& write) const {
        try {
            write();
        } catch (const Error& e) {
            rethrowNamingFinal(e);
        }
    }

private:
    friend void commitTogether(const std::vector<AtomicOutput*>& outputs);
    void sync() const;  // fsyncs the temporary file; errors name the final path
    [[noreturn]] void rethrowNamingFinal(const Error& e) const;

    std::filesystem::path final_;
    std::filesystem::path temp_;
    int slot_ = -1;  // index in the live-temp registry, -1 when not registered
    bool committed_ = false;
};

// Renames several outputs into place, all or none: the files of one run replace the previous set
// together or leave it byte-identical. Every temporary file is flushed first (a failure renames
// nothing); each target that exists is kept under a hidden name beside it (a hard link, or a copy
// where the file system has none); then the renames; if one fails, those already renamed are put
// back (the kept file renamed over the new one, a new file removed) and the error names the file
// that failed. Outputs already committed are skipped; null entries are ignored. Only a crash
// during the renames themselves (microseconds) can leave a mix, and a kept ".name.old-…" file.
void commitTogether(const std::vector<AtomicOutput*>& outputs);

// Writes `bytes` to `path` through an AtomicOutput: readers see the old file or the whole new one.
// Errors name the path.
void writeFileAtomically(const std::filesystem::path& path, const std::string& bytes);

// Unlinks every temporary file of a live AtomicOutput. Async-signal-safe (reads a fixed
// registry and calls only unlink()), for SIGINT/SIGTERM handlers; the process should exit next.
void removeLiveTempFiles() noexcept;

// Puts another file (a batch job's claim, batch/job_claim.h) in the same registry, so that a
// signal removes it too. Returns the slot for unregisterRemoveOnSignal, or -1 when the registry is
// full (the file then stays after a signal; its owner's death is still detectable).
int registerRemoveOnSignal(const std::string& path);
void unregisterRemoveOnSignal(int slot);

// Number of temporary files currently registered (tests).
int liveTempFileCount() noexcept;

}  // namespace metamer
