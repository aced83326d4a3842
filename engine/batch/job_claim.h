// One writer per job: before a batch renders a job (or clears the job folder's temporaries) it
// claims the folder by creating DIR/<id>/.claim with O_CREAT|O_EXCL — atomic on a local file
// system and on NFS v3 and later — holding its owner: host, boot, pid and the pid's start time. A
// claim is broken only when its owner is provably gone: the same host and boot with that pid no
// longer running (or running another program since), or the same host rebooted since. A claim
// from another host is kept (its process cannot be seen from here) unless the user says that run
// is gone (--break-claims). docs/batch.md, "Two runs at once". Tests: engine/batch/job_claim_test.cpp.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace metamer {

// Who holds a claim, as written in the claim file (one line: host boot pid start).
struct ClaimOwner {
    std::string host, boot;          // gethostname(); /proc/sys/kernel/random/boot_id
    long pid = 0;
    unsigned long long start = 0;    // the pid's start time, clock ticks after boot (/proc/PID/stat)

    static ClaimOwner self();
    std::string text() const;        // "host pid" for messages
};

// Whether `owner` is provably gone, seen from this process.
bool claimOwnerIsGone(const ClaimOwner& owner);

class JobClaim {
public:
    // Claims `folder` (created if missing). When another live (or unprovably dead) owner holds it,
    // returns nothing and says who in `heldBy`. A claim whose owner is gone — or any claim, with
    // `breakAny` — is broken under a second O_EXCL claim (.claim.breaking), and only if it is still
    // the file that was judged (inode, time, text), so of several runs breaking it one wins and a
    // claim made meanwhile is never removed; then the folder is claimed. Errors other than "held"
    // (a folder that cannot be written) throw.
    static std::optional<JobClaim> tryClaim(const std::filesystem::path& folder, bool breakAny, std::string& heldBy);

    JobClaim(JobClaim&& other) noexcept;
    JobClaim& operator=(JobClaim&& other) noexcept;  // releases this claim, takes the other's
    JobClaim(const JobClaim&) = delete;
    ~JobClaim();  // releases the claim (removes the file)

private:
    void release() noexcept;

public:

private:
    explicit JobClaim(std::filesystem::path file);
    std::filesystem::path file_;
    int slot_ = -1;  // removed on SIGINT/SIGTERM with the temporaries (io/atomic_file.h)
};

constexpr const char* kClaimFile = ".claim";

}  // namespace metamer
