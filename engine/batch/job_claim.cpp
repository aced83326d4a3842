#include "batch/job_claim.h"

#include "core/error.h"
#include "io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace metamer {

namespace {

std::string firstLine(const fs::path& p) {
    std::ifstream in(p);
    std::string line;
    std::getline(in, line);
    return line;
}

// Field 22 of /proc/PID/stat (after the command name, which may hold spaces and parentheses).
std::optional<unsigned long long> startTimeOf(long pid) {
    std::ifstream in(fmt::format("/proc/{}/stat", pid));
    std::string stat;
    if (!std::getline(in, stat)) return std::nullopt;
    const size_t close = stat.rfind(')');
    if (close == std::string::npos) return std::nullopt;
    std::istringstream rest(stat.substr(close + 2));
    std::string field;
    for (int i = 3; i <= 22; ++i)
        if (!(rest >> field)) return std::nullopt;
    try {
        return std::stoull(field);
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

std::optional<ClaimOwner> parseOwner(const std::string& line) {
    std::istringstream in(line);
    ClaimOwner o;
    if (!(in >> o.host >> o.boot >> o.pid >> o.start) || o.pid <= 0) return std::nullopt;
    return o;
}

// O_EXCL: exactly one of several runs creating the file at once succeeds.
bool createExclusively(const fs::path& file, const std::string& text) {
    const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) {
        if (errno == EEXIST) return false;
        failRuntime("cannot claim {}: {}", file.string(), std::strerror(errno));
    }
    const bool ok = ::write(fd, text.data(), text.size()) == ssize_t(text.size()) && ::fsync(fd) == 0;
    ::close(fd);
    if (!ok) {
        ::unlink(file.c_str());
        failRuntime("cannot write the claim {}", file.string());
    }
    return true;
}

}  // namespace

ClaimOwner ClaimOwner::self() {
    ClaimOwner o;
    char host[256] = {};
    ::gethostname(host, sizeof host - 1);
    o.host = host[0] ? host : "unknown-host";
    o.boot = firstLine("/proc/sys/kernel/random/boot_id");
    if (o.boot.empty()) o.boot = "unknown-boot";
    o.pid = ::getpid();
    o.start = startTimeOf(o.pid).value_or(0);
    return o;
}

std::string ClaimOwner::text() const { return fmt::format("{} pid {}", host, pid); }

bool claimOwnerIsGone(const ClaimOwner& owner) {
    const ClaimOwner me = ClaimOwner::self();
    if (owner.host != me.host) return false;  // another machine's processes cannot be seen from here
    if (owner.boot != me.boot) return true;   // this machine has restarted since
    const std::optional<unsigned long long> start = startTimeOf(owner.pid);
    return !start || *start != owner.start;  // no such process, or the pid now names another one
}

JobClaim::JobClaim(fs::path file) : file_(std::move(file)), slot_(registerRemoveOnSignal(file_.string())) {}

JobClaim::JobClaim(JobClaim&& other) noexcept : file_(std::move(other.file_)), slot_(other.slot_) {
    other.file_.clear();
    other.slot_ = -1;
}

JobClaim& JobClaim::operator=(JobClaim&& other) noexcept {
    if (this != &other) {
        release();
        file_ = std::move(other.file_);
        slot_ = other.slot_;
        other.file_.clear();
        other.slot_ = -1;
    }
    return *this;
}

JobClaim::~JobClaim() { release(); }

void JobClaim::release() noexcept {
    if (file_.empty()) return;
    unregisterRemoveOnSignal(slot_);
    std::error_code ec;
    fs::remove(file_, ec);
    file_.clear();
    slot_ = -1;
}

std::optional<JobClaim> JobClaim::tryClaim(const fs::path& folder, bool breakAny, std::string& heldBy) {
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec) failRuntime("cannot create {}: {}", folder.string(), ec.message());
    const fs::path file = folder / kClaimFile;
    const ClaimOwner me = ClaimOwner::self();
    const std::string mine = fmt::format("{} {} {} {}\n", me.host, me.boot, me.pid, me.start);
    for (int attempt = 0; attempt < 5; ++attempt) {
        if (createExclusively(file, mine)) return JobClaim(file);
        struct stat judged {};
        if (::stat(file.c_str(), &judged) != 0) continue;  // released since: try again
        const std::string line = firstLine(file);
        const std::optional<ClaimOwner> owner = parseOwner(line);
        // A claim being written this instant reads empty: held, not damaged — unless it has been
        // empty for a minute (its writer died between creating and writing it).
        const bool beingWritten =
            line.empty() && fs::last_write_time(file, ec) > fs::file_time_type::clock::now() - std::chrono::minutes(1);
        if (!breakAny && (beingWritten || (owner && !claimOwnerIsGone(*owner)))) {
            heldBy = owner ? owner->text() : "a run that is writing its claim now";
            return std::nullopt;
        }
        // Broken under a second claim, .claim.breaking, so that of several runs that found it stale
        // one breaks it, and only if it is still the file it judged (inode, time, text): a claim made
        // since by a live run is never removed.
        const fs::path breaking = folder / ".claim.breaking";
        if (!createExclusively(breaking, mine)) {
            if (fs::last_write_time(breaking, ec) < fs::file_time_type::clock::now() - std::chrono::minutes(1) && !ec)
                fs::remove(breaking, ec);  // its breaker died within those milliseconds
            else {
                heldBy = "another run (breaking a stale claim now)";
                return std::nullopt;
            }
            continue;
        }
        struct stat now {};
        if (::stat(file.c_str(), &now) == 0 && now.st_ino == judged.st_ino && now.st_dev == judged.st_dev &&
            now.st_mtim.tv_sec == judged.st_mtim.tv_sec && now.st_mtim.tv_nsec == judged.st_mtim.tv_nsec &&
            firstLine(file) == line)  // an inode number can be reused by a new claim; its time and text differ
            ::unlink(file.c_str());
        ::unlink(breaking.c_str());
    }
    heldBy = "another run (the claim kept changing)";
    return std::nullopt;
}

}  // namespace metamer
