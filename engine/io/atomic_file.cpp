#include "io/atomic_file.h"

#include "core/error.h"

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

int registerTemp(const std::string& path) {
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

void unregisterTemp(int slot) {
    if (slot >= 0) g_slots[slot].state.store(Free, std::memory_order_release);
}

}  // namespace

AtomicOutput::AtomicOutput(fs::path finalPath) : final_(std::move(finalPath)) {
    if (final_.filename().empty())
        failRuntime("output path '{}' names a folder, not a file", final_.string());
    fs::path dir = final_.parent_path();
    if (!dir.empty()) {
        std::error_code ec;
        fs::create_directories(dir, ec);
        if (ec) failRuntime("cannot create output folder '{}': {}", dir.string(), ec.message());
    }
    std::string name = fmt::format(".{}.tmp-{}-{}{}", final_.filename().string(), ::getpid(),
                                   g_counter.fetch_add(1), final_.extension().string());
    temp_ = dir / name;
    slot_ = registerTemp(temp_.string());
}

AtomicOutput::~AtomicOutput() {
    if (!committed_) ::unlink(temp_.c_str());  // may not exist yet: ignore ENOENT
    unregisterTemp(slot_);
}

void AtomicOutput::commit() {
    if (committed_) return;
    // Flush the data before the rename, or a crash could leave an empty file under the final name.
    int fd = ::open(temp_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        failRuntime("cannot write '{}': temporary file '{}' is missing ({})", final_.string(),
                    temp_.string(), std::strerror(errno));
    int syncErr = ::fsync(fd) == 0 ? 0 : errno;
    ::close(fd);
    if (syncErr != 0)
        failRuntime("cannot write '{}': fsync failed: {}", final_.string(), std::strerror(syncErr));
    if (::rename(temp_.c_str(), final_.c_str()) != 0)
        failRuntime("cannot write '{}': rename from '{}' failed: {}", final_.string(),
                    temp_.string(), std::strerror(errno));
    committed_ = true;
    unregisterTemp(slot_);  // after the rename: a signal in between finds no file, harmless
    slot_ = -1;
    // Make the rename itself durable; failure here does not undo a completed write.
    fs::path dir = final_.parent_path().empty() ? fs::path(".") : final_.parent_path();
    int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        ::fsync(dfd);
        ::close(dfd);
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
