#include "io/atomic_file.h"

#include "core/error.h"
#include "core/file_reads.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <dirent.h>
#include <fcntl.h>
#include <fstream>
#include <sys/stat.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace metamer {

namespace {

// The live-temp registry. A signal handler may only touch lock-free atomics and plain memory, so
// paths live in fixed buffers, and a slot is published (state Live) only once its path is
// complete. Outputs beyond the registry's capacity still work; they are just not cleaned up on a
// signal.
constexpr int kSlots = 64;
constexpr size_t kPathBytes = 4096;
enum SlotState : int { Free = 0, Filling = 1, Live = 2 };

struct Slot {
    std::atomic<int> state{Free};
    bool folder = false;  // a staging folder: emptied, then removed
    char path[kPathBytes];
};
static_assert(std::atomic<int>::is_always_lock_free);

Slot g_slots[kSlots];
std::atomic<unsigned> g_counter{0};

}  // namespace

namespace {

int registerSlot(const std::string& path, bool folder) {
    if (path.size() + 1 > kPathBytes) return -1;
    for (int i = 0; i < kSlots; ++i) {
        int expected = Free;
        if (!g_slots[i].state.compare_exchange_strong(expected, Filling)) continue;
        g_slots[i].folder = folder;
        std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
        g_slots[i].state.store(Live, std::memory_order_release);
        return i;
    }
    return -1;
}

// Unlinks everything in a folder, then the folder, with async-signal-safe calls only (no
// opendir: it allocates). Passes repeat until one finds nothing, as unlinking while reading a
// folder may hide entries from the same pass.
void emptyAndRemoveFolder(const char* path) noexcept {
    const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        alignas(8) char buf[4096];
        for (int pass = 0; pass < 64; ++pass) {
            bool removed = false;
            ::lseek(fd, 0, SEEK_SET);
            for (ssize_t n; (n = ::getdents64(fd, buf, sizeof buf)) > 0;)
                for (ssize_t at = 0; at < n;) {
                    const auto* d = reinterpret_cast<const struct dirent64*>(buf + at);
                    at += d->d_reclen;
                    const char* name = d->d_name;
                    if (name[0] == '.' && (name[1] == 0 || (name[1] == '.' && name[2] == 0))) continue;
                    if (::unlinkat(fd, name, 0) == 0) removed = true;
                }
            if (!removed) break;
        }
        ::close(fd);
    }
    ::rmdir(path);
}

}  // namespace

int registerRemoveOnSignal(const std::string& path) { return registerSlot(path, false); }

namespace {

// What is at an output's target now: a file or a symbolic link is replaced (the link itself, not
// what it points to); anything else would fail (a folder) or be replaced unawares (a FIFO, a
// device) only at the rename, after the work.
void requireReplaceable(const fs::path& target) {
    std::error_code ec;
    const fs::file_status st = fs::symlink_status(target, ec);
    if (fs::exists(st) && !fs::is_regular_file(st) && !fs::is_symlink(st))
        failRuntime("cannot write '{}': it is {}; an output replaces a file (remove it or write elsewhere)",
                    target.string(), specialFileKind(st));
}

}  // namespace

void unregisterRemoveOnSignal(int slot) {
    if (slot >= 0) g_slots[slot].state.store(Free, std::memory_order_release);
}

AtomicOutput::AtomicOutput(fs::path finalPath) : final_(std::move(finalPath)) {
    if (final_.filename().empty())
        failRuntime("output path '{}' names a folder, not a file", final_.string());
    fs::path dir = final_.parent_path();
    if (!dir.empty()) {
        std::error_code ec;
        const fs::file_status st = fs::status(dir, ec);
        if (fs::exists(st) && !fs::is_directory(st))
            failRuntime("cannot write '{}': '{}' is not a folder ({})", final_.string(), dir.string(),
                        fs::is_regular_file(st) ? "a file" : specialFileKind(st));
        fs::create_directories(dir, ec);
        if (ec) failRuntime("cannot create output folder '{}': {}", dir.string(), ec.message());
    }
    requireReplaceable(final_);
    std::string name = fmt::format(".{}.tmp-{}-{}{}", final_.filename().string(), ::getpid(),
                                   g_counter.fetch_add(1), final_.extension().string());
    temp_ = dir / name;
    slot_ = registerRemoveOnSignal(temp_.string());
    const int fd = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) {
        const int err = errno;
        unregisterRemoveOnSignal(slot_);
        slot_ = -1;
        failRuntime("cannot write '{}': cannot create a file in '{}': {}", final_.string(),
                    dir.empty() ? std::string(".") : dir.string(), std::strerror(err));
    }
    ::close(fd);
}

AtomicOutput::~AtomicOutput() {
    if (!committed_) ::unlink(temp_.c_str());  // may not exist yet: ignore ENOENT
    unregisterRemoveOnSignal(slot_);
}

void AtomicOutput::sync() const {
    // Flush the data before the rename, or a crash could leave an empty file under the final name.
    int fd = ::open(temp_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        failRuntime("cannot write '{}': temporary file '{}' is missing ({})", final_.string(),
                    temp_.string(), std::strerror(errno));
    int syncErr = ::fsync(fd) == 0 ? 0 : errno;
    ::close(fd);
    if (syncErr != 0)
        failRuntime("cannot write '{}': fsync failed: {}", final_.string(), std::strerror(syncErr));
}

void AtomicOutput::commit() { commitTogether({this}); }

void AtomicOutput::rethrowNamingFinal(const Error& e) const { rethrowNaming(e, temp_.string(), final_.string()); }

void rethrowNaming(const Error& e, const std::string& from, const std::string& to) {
    std::string text = e.message();
    for (size_t at = 0; !from.empty() && (at = text.find(from, at)) != std::string::npos; at += to.size())
        text.replace(at, from.size(), to);
    Where where = e.where();
    if (where.file == from) where.file = to;
    throw Error(e.code(), where, text);
}

namespace {

fs::path folderOf(const fs::path& p) { return p.parent_path().empty() ? fs::path(".") : p.parent_path(); }

// A hidden name beside `target` for its previous content while a set of outputs is renamed.
fs::path keptName(const fs::path& target) {
    return folderOf(target) /
           fmt::format(".{}.old-{}-{}", target.filename().string(), ::getpid(), g_counter.fetch_add(1));
}

}  // namespace

StagingFolder::StagingFolder(fs::path target, std::string name) : target_(std::move(target)), name_(std::move(name)) {}

StagingFolder::~StagingFolder() {
    std::error_code ec;
    if (!folder_.empty()) fs::remove_all(folder_, ec);  // empty after a commit; else what was staged
    unregisterRemoveOnSignal(slot_);
}

fs::path StagingFolder::stage(const std::string& filename) {
    if (folder_.empty()) {
        std::error_code ec;
        const fs::file_status st = fs::status(target_, ec);
        if (fs::exists(st) && !fs::is_directory(st))
            failRuntime("cannot write in '{}': it is not a folder ({})", target_.string(),
                        fs::is_regular_file(st) ? "a file" : specialFileKind(st));
        fs::create_directories(target_, ec);
        if (ec) failRuntime("cannot create output folder '{}': {}", target_.string(), ec.message());
        const fs::path folder = target_ / fmt::format(".{}.staging-{}-{}", name_, ::getpid(), g_counter.fetch_add(1));
        slot_ = registerSlot(folder.string(), true);
        if (::mkdir(folder.c_str(), 0777) != 0) {
            const int err = errno;
            unregisterRemoveOnSignal(slot_);
            slot_ = -1;
            failRuntime("cannot write in '{}': cannot create a folder there to stage its files in: {}",
                        target_.string(), std::strerror(err));
        }
        folder_ = folder;
    }
    if (filename.empty() || filename.find('/') != std::string::npos || filename == "." || filename == "..")
        failRuntime("cannot stage '{}' in '{}': expected a file name", filename, target_.string());
    if (std::find(names_.begin(), names_.end(), filename) != names_.end())
        failRuntime("cannot write '{}' twice in one run", (target_ / filename).string());
    requireReplaceable(target_ / filename);
    names_.push_back(filename);
    return folder_ / filename;
}

bool isStagingFolderName(const std::string& name) {
    return name.size() > 1 && name[0] == '.' && name.find(".staging-") != std::string::npos;
}

namespace {

struct Move {
    fs::path from, to;
};

}  // namespace

void commitTogether(const std::vector<AtomicOutput*>& all, const std::vector<StagingFolder*>& allStaged) {
    std::vector<AtomicOutput*> outs;
    for (AtomicOutput* o : all)
        if (o && !o->committed_) outs.push_back(o);
    std::vector<StagingFolder*> staged;
    for (StagingFolder* f : allStaged)
        if (f && !f->committed_) staged.push_back(f);
    if (outs.empty() && staged.empty()) return;
    for (const AtomicOutput* o : outs) o->sync();

    std::vector<Move> moves;
    for (const AtomicOutput* o : outs) moves.push_back({o->temp_, o->final_});
    for (const StagingFolder* f : staged)
        for (const std::string& name : f->names_) {
            const fs::path from = f->folder_ / name;
            std::error_code ec;
            if (!fs::is_regular_file(fs::symlink_status(from, ec)))
                failRuntime("cannot write '{}': its staged file '{}' is missing", (f->target_ / name).string(),
                            from.string());
            moves.push_back({from, f->target_ / name});
        }

    // The previous set, kept until every new file is in place: inside a staging folder when there
    // is one (its registry entry covers them, however many), else beside each target, registered
    // like temporary files. A signal during the renames removes them too.
    const StagingFolder* keepIn = nullptr;
    for (const StagingFolder* f : staged)
        if (!keepIn && !f->folder_.empty()) keepIn = f;
    std::vector<fs::path> kept(moves.size());
    std::vector<int> keptSlots(moves.size(), -1);
    auto dropKept = [&] {
        for (size_t i = 0; i < kept.size(); ++i) {
            if (!kept[i].empty()) ::unlink(kept[i].c_str()), kept[i].clear();
            unregisterRemoveOnSignal(keptSlots[i]);
            keptSlots[i] = -1;
        }
    };
    for (size_t i = 0; i < moves.size(); ++i) {
        const fs::path& target = moves[i].to;
        std::error_code ec;
        const fs::file_status st = fs::symlink_status(target, ec);
        // Nothing there, or something a rename cannot replace (a folder made since the output was
        // opened: its rename fails below and the set is put back).
        if (!fs::exists(st) || (!fs::is_regular_file(st) && !fs::is_symlink(st))) continue;
        const fs::path k = keepIn ? keepIn->folder_ / fmt::format(".old-{}-{}", g_counter.fetch_add(1),
                                                                  target.filename().string())
                                  : keptName(target);
        if (!keepIn) keptSlots[i] = registerRemoveOnSignal(k.string());
        if (::link(target.c_str(), k.c_str()) != 0) {  // no hard links here (e.g. FAT): a copy
            fs::copy(target, k, fs::copy_options::copy_symlinks, ec);
            if (ec) {
                unregisterRemoveOnSignal(keptSlots[i]);
                keptSlots[i] = -1;
                dropKept();
                failRuntime("cannot write '{}': cannot keep the previous file as '{}' while the new set is put in "
                            "place: {}", target.string(), k.string(), ec.message());
            }
        }
        kept[i] = k;
    }

    size_t renamed = 0;
    int err = 0;
    for (; renamed < moves.size(); ++renamed)
        if (::rename(moves[renamed].from.c_str(), moves[renamed].to.c_str()) != 0) {
            err = errno;
            break;
        }
    if (renamed < moves.size()) {
        // Put the previous set back: each kept file over the new one, new files that had none removed.
        for (size_t j = 0; j < renamed; ++j) {
            const fs::path& target = moves[j].to;
            if (kept[j].empty()) ::unlink(target.c_str());
            else if (::rename(kept[j].c_str(), target.c_str()) == 0) kept[j].clear();  // slot freed by dropKept
        }
        dropKept();
        failRuntime("cannot write '{}': rename from '{}' failed: {}{}", moves[renamed].to.string(),
                    moves[renamed].from.string(), std::strerror(err),
                    renamed ? "; the other files of this run were not put in place (the previous ones are kept)"
                            : "");
    }
    dropKept();
    std::vector<fs::path> folders;
    for (AtomicOutput* o : outs) {
        o->committed_ = true;
        unregisterRemoveOnSignal(o->slot_);  // after the rename: a signal in between finds no file, harmless
        o->slot_ = -1;
    }
    for (StagingFolder* f : staged) {
        f->committed_ = true;
        if (!f->folder_.empty()) ::rmdir(f->folder_.c_str());  // empty now; the destructor removes anything else
    }
    for (const Move& m : moves) {
        const fs::path dir = folderOf(m.to);
        if (std::find(folders.begin(), folders.end(), dir) == folders.end()) folders.push_back(dir);
    }
    // Make the renames themselves durable; failure here does not undo a completed write.
    for (const fs::path& dir : folders) {
        int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        if (dfd >= 0) {
            ::fsync(dfd);
            ::close(dfd);
        }
    }
}

void removeLiveTempFiles() noexcept {
    for (int i = 0; i < kSlots; ++i)
        if (g_slots[i].state.load(std::memory_order_acquire) == Live) {
            if (g_slots[i].folder) emptyAndRemoveFolder(g_slots[i].path);
            else ::unlink(g_slots[i].path);
        }
}

int liveTempFileCount() noexcept {
    int n = 0;
    for (int i = 0; i < kSlots; ++i)
        if (g_slots[i].state.load(std::memory_order_acquire) == Live) ++n;
    return n;
}

void writeFileAtomically(const fs::path& path, const std::string& bytes) {
    AtomicOutput out(path);
    {
        std::ofstream f(out.tempPath(), std::ios::binary);
        f << bytes;
        f.close();
        if (!f) failRuntime("cannot write '{}': write failed", path.string());
    }
    out.commit();
}

}  // namespace metamer
