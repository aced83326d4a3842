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

class StagingFolder;

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
    friend void commitTogether(const std::vector<AtomicOutput*>& outputs, const std::vector<StagingFolder*>& staged);
    void sync() const;  // fsyncs the temporary file; errors name the final path
    [[noreturn]] void rethrowNamingFinal(const Error& e) const;

    std::filesystem::path final_;
    std::filesystem::path temp_;
    int slot_ = -1;  // index in the live-temp registry, -1 when not registered
    bool committed_ = false;
};

// A hidden folder beside a set of outputs that holds them whole until they are renamed into place
// together (commitTogether): a capture's thousands of frames, written one by one with the ordinary
// writers, appear with the render they belong to or not at all. One entry of the signal registry
// covers every file in it, however many. The folder and what is left in it go with the object.
class StagingFolder {
public:
    // The folder, target/.NAME.staging-PID-N/ (and `target` if missing), is made by the first
    // stage(), so a run refused before it writes anything creates nothing; errors name it.
    StagingFolder(std::filesystem::path target, std::string name);
    ~StagingFolder();
    StagingFolder(const StagingFolder&) = delete;
    StagingFolder& operator=(const StagingFolder&) = delete;

    // Where to write the file that becomes target/`filename` at commit (write it whole there,
    // e.g. through writeImage or writeFileAtomically).
    std::filesystem::path stage(const std::string& filename);
    // What it will be called once committed.
    std::filesystem::path finalPath(const std::string& filename) const { return target_ / filename; }
    const std::filesystem::path& target() const { return target_; }
    const std::filesystem::path& folder() const { return folder_; }  // empty until the first stage()
    size_t size() const { return names_.size(); }

private:
    friend void commitTogether(const std::vector<AtomicOutput*>& outputs, const std::vector<StagingFolder*>& staged);
    std::filesystem::path target_, folder_;
    std::string name_;
    std::vector<std::string> names_;
    int slot_ = -1;
    bool committed_ = false;
};

// Renames several outputs into place, all or none: the files of one run replace the previous set
// together or leave it byte-identical. Files staged in StagingFolders join the same set (their
// previous files are kept inside the staging folder while the set is put in place). Every temporary file is flushed first (a failure renames
// nothing); each target that exists is kept under a hidden name beside it (a hard link, or a copy
// where the file system has none); then the renames; if one fails, those already renamed are put
// back (the kept file renamed over the new one, a new file removed) and the error names the file
// that failed. Outputs already committed are skipped; null entries are ignored. Only a crash
// during the renames themselves (microseconds) can leave a mix, and a kept ".name.old-…" file.
void commitTogether(const std::vector<AtomicOutput*>& outputs, const std::vector<StagingFolder*>& staged = {});

// A hidden staging folder's name (".NAME.staging-PID-N"): batch jobs remove those a killed run left.
bool isStagingFolderName(const std::string& filename);

// Throws `e` again with every `from` in its message replaced by `to`: a library's message about a
// temporary or staged file names the file the user asked for.
[[noreturn]] void rethrowNaming(const Error& e, const std::string& from, const std::string& to);

// Writes `bytes` to `path` through an AtomicOutput: readers see the old file or the whole new one.
// Errors name the path.
void writeFileAtomically(const std::filesystem::path& path, const std::string& bytes);

// Unlinks every temporary file of a live AtomicOutput and empties and removes every live staging
// folder. Async-signal-safe (reads a fixed registry and calls only open, getdents64, unlinkat,
// close, rmdir and unlink), for SIGINT/SIGTERM handlers; the process should exit next.
void removeLiveTempFiles() noexcept;

// Puts another file (a batch job's claim, batch/job_claim.h) in the same registry, so that a
// signal removes it too. Returns the slot for unregisterRemoveOnSignal, or -1 when the registry is
// full (the file then stays after a signal; its owner's death is still detectable).
int registerRemoveOnSignal(const std::string& path);
void unregisterRemoveOnSignal(int slot);

// Entries currently registered: temporary files and staging folders (tests).
int liveTempFileCount() noexcept;

}  // namespace metamer
