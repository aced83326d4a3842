#include "io/atomic_file.h"

#include "core/error.h"
#include "core/file_reads.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <fstream>
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
    char path[kPathBytes];
};
static_assert(std::atomic<int>::is_always_lock_free);

Slot g_slots[kSlots];
std::atomic<unsigned> g_counter{0};

}  // namespace

int registerRemoveOnSignal(const std::string& path) {
    if (path.size() + 1 > kPathBytes) return -1;
    for (int i = 0; i < kSlots; ++i) {
        int expected = Free;
        if (!g_slots[i].state.compare_exchange_strong(expected, Filling)) continue;
        std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
        g_slots[i].state.store(Live, std::memory_order_release);
        return i;
    }
    return -1;
}

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
    // What is at the target now: a file or a symbolic link is replaced (the link itself, not what
    // it points to); anything else would fail only at the rename, after the work.
    {
        std::error_code ec;
        const fs::file_status st = fs::symlink_status(final_, ec);
        if (fs::exists(st) && !fs::is_regular_file(st) && !fs::is_symlink(st))
            failRuntime("cannot write '{}': it is {}; an output replaces a file (remove it or write elsewhere)",
                        final_.string(), specialFileKind(st));
    }
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

void AtomicOutput::rethrowNamingFinal(const Error& e) const {
    std::string text = e.message();
    const std::string temp = temp_.string(), final = final_.string();
    for (size_t at = 0; (at = text.find(temp, at)) != std::string::npos; at += final.size())
        text.replace(at, temp.size(), final);
    throw Error(e.code(), e.where(), text);
}

namespace {

fs::path folderOf(const fs::path& p) { return p.parent_path().empty() ? fs::path(".") : p.parent_path(); }

// A hidden name beside `target` for its previous content while a set of outputs is renamed.
fs::path keptName(const fs::path& target) {
    return folderOf(target) /
           fmt::format(".{}.old-{}-{}", target.filename().string(), ::getpid(), g_counter.fetch_add(1));
}

}  // namespace

void commitTogether(const std::vector<AtomicOutput*>& all) {
    std::vector<AtomicOutput*> outs;
    for (AtomicOutput* o : all)
        if (o && !o->committed_) outs.push_back(o);
    if (outs.empty()) return;
    for (const AtomicOutput* o : outs) o->sync();

    // The previous set, kept until every new file is in place.
    // They are registered like temporary files: a signal during the renames removes them too.
    std::vector<fs::path> kept(outs.size());
    std::vector<int> keptSlots(outs.size(), -1);
    auto dropKept = [&] {
        for (size_t i = 0; i < kept.size(); ++i) {
            if (!kept[i].empty()) ::unlink(kept[i].c_str()), kept[i].clear();
            unregisterRemoveOnSignal(keptSlots[i]);
            keptSlots[i] = -1;
        }
    };
    for (size_t i = 0; i < outs.size(); ++i) {
        const fs::path& target = outs[i]->final_;
        std::error_code ec;
        const fs::file_status st = fs::symlink_status(target, ec);
        // Nothing there, or something a rename cannot replace (a folder made since the output was
        // opened: its rename fails below and the set is put back).
        if (!fs::exists(st) || (!fs::is_regular_file(st) && !fs::is_symlink(st))) continue;
        const fs::path k = keptName(target);
        keptSlots[i] = registerRemoveOnSignal(k.string());
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
    for (; renamed < outs.size(); ++renamed)
        if (::rename(outs[renamed]->temp_.c_str(), outs[renamed]->final_.c_str()) != 0) {
            err = errno;
            break;
        }
    if (renamed < outs.size()) {
        // Put the previous set back: each kept file over the new one, new files that had none removed.
        for (size_t j = 0; j < renamed; ++j) {
            const fs::path& target = outs[j]->final_;
            if (kept[j].empty()) ::unlink(target.c_str());
            else if (::rename(kept[j].c_str(), target.c_str()) == 0) kept[j].clear();  // slot freed by dropKept
        }
        dropKept();
        failRuntime("cannot write '{}': rename from '{}' failed: {}{}", outs[renamed]->final_.string(),
                    outs[renamed]->temp_.string(), std::strerror(err),
                    renamed ? "; the other files of this run were not put in place (the previous ones are kept)"
                            : "");
    }
    dropKept();
    std::vector<fs::path> folders;
    for (AtomicOutput* o : outs) {
        o->committed_ = true;
        unregisterRemoveOnSignal(o->slot_);  // after the rename: a signal in between finds no file, harmless
        o->slot_ = -1;
        const fs::path dir = folderOf(o->final_);
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
        if (g_slots[i].state.load(std::memory_order_acquire) == Live) ::unlink(g_slots[i].path);
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
