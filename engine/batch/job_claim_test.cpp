// One writer per job (batch/job_claim): a claim is held against every other run while its owner
// lives, broken when the owner is provably gone (a dead pid, a reused pid, a restarted host, a
// damaged or long-empty file), kept when it cannot be proved (another host) unless the user says
// so, and of several processes racing for one folder exactly one wins.
#include "batch/job_claim.h"

#include "core/error.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <thread>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

fs::path freshFolder(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / fmt::format("metamer-claim-test-{}", ::getpid()) / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

void writeClaim(const fs::path& folder, const std::string& line) { std::ofstream(folder / kClaimFile) << line; }

std::string claimLine(const ClaimOwner& o) { return fmt::format("{} {} {} {}\n", o.host, o.boot, o.pid, o.start); }

// A pid that has certainly ended: a child that exited and was reaped.
long deadPid() {
    const pid_t child = ::fork();
    if (child == 0) ::_exit(0);
    int status = 0;
    ::waitpid(child, &status, 0);
    return child;
}

}  // namespace

TEST(JobClaim, HeldWhileItsOwnerLivesAndFreeOnceReleased) {
    const fs::path f = freshFolder("live");
    std::string heldBy;
    {
        std::optional<JobClaim> mine = JobClaim::tryClaim(f, false, heldBy);
        ASSERT_TRUE(mine.has_value());
        EXPECT_TRUE(fs::exists(f / kClaimFile));
        // Another run (here: this process again) finds it held, and by whom.
        EXPECT_FALSE(JobClaim::tryClaim(f, false, heldBy).has_value());
        EXPECT_EQ(heldBy, ClaimOwner::self().text());
        EXPECT_TRUE(fs::exists(f / kClaimFile));
    }
    EXPECT_FALSE(fs::exists(f / kClaimFile));
    EXPECT_TRUE(JobClaim::tryClaim(f, false, heldBy).has_value());
}

TEST(JobClaim, BrokenOnlyWhenItsOwnerIsProvablyGone) {
    const ClaimOwner me = ClaimOwner::self();
    std::string heldBy;
    struct Case {
        const char* what;
        std::string line;
        bool gone;
    };
    ClaimOwner dead = me, reused = me, rebooted = me, elsewhere = me;
    dead.pid = deadPid();
    reused.start = me.start + 12345;  // this pid, but started at another time: another process
    rebooted.boot = "00000000-0000-0000-0000-000000000000";
    elsewhere.host = "node-" + me.host + "-other";
    const Case cases[] = {
        {"a dead pid", claimLine(dead), true},
        {"a reused pid", claimLine(reused), true},
        {"a restarted host", claimLine(rebooted), true},
        {"damaged", "\x01\x02 not a claim", true},
        {"a live owner", claimLine(me), false},
        {"another host", claimLine(elsewhere), false},
        {"being written (empty, new)", "", false},
    };
    for (const Case& c : cases) {
        const fs::path f = freshFolder("gone");
        writeClaim(f, c.line);
        const std::optional<JobClaim> claim = JobClaim::tryClaim(f, false, heldBy);
        EXPECT_EQ(claim.has_value(), c.gone) << c.what;
        if (!c.gone) EXPECT_TRUE(fs::exists(f / kClaimFile)) << c.what;  // a held claim is left as it was
        std::error_code ec;
        for (const auto& e : fs::directory_iterator(f, ec))
            EXPECT_EQ(e.path().filename().string().find("broken"), std::string::npos) << c.what;
    }
    // Another host's claim: left alone unless the user says that run is gone.
    const fs::path f = freshFolder("elsewhere");
    writeClaim(f, claimLine(elsewhere));
    EXPECT_FALSE(JobClaim::tryClaim(f, false, heldBy).has_value());
    EXPECT_EQ(heldBy, elsewhere.text());
    EXPECT_TRUE(JobClaim::tryClaim(f, true, heldBy).has_value());
    // An empty claim a minute old: its writer died between creating and writing it.
    const fs::path e = freshFolder("empty-old");
    writeClaim(e, "");
    fs::last_write_time(e / kClaimFile, fs::file_time_type::clock::now() - std::chrono::minutes(2));
    EXPECT_TRUE(JobClaim::tryClaim(e, false, heldBy).has_value());
}

TEST(JobClaim, OfManyProcessesRacingForOneFolderExactlyOneWins) {
    for (const bool stale : {false, true}) {
        const fs::path f = freshFolder(stale ? "race-stale" : "race");
        if (stale) {  // all of them also race to break the same stale claim
            ClaimOwner dead = ClaimOwner::self();
            dead.pid = deadPid();
            writeClaim(f, claimLine(dead));
        }
        std::vector<pid_t> children;
        for (int i = 0; i < 8; ++i) {
            const pid_t c = ::fork();
            if (c == 0) {
                std::string heldBy;
                int code = 2;
                try {
                    const std::optional<JobClaim> claim = JobClaim::tryClaim(f, false, heldBy);
                    code = claim ? 0 : 1;
                    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // hold it while the others try
                } catch (...) {
                }
                ::_exit(code);
            }
            children.push_back(c);
        }
        int winners = 0, errors = 0;
        for (const pid_t c : children) {
            int status = 0;
            ::waitpid(c, &status, 0);
            winners += WIFEXITED(status) && WEXITSTATUS(status) == 0;
            errors += !WIFEXITED(status) || WEXITSTATUS(status) == 2;
        }
        EXPECT_EQ(winners, 1) << (stale ? "breaking a stale claim" : "a fresh folder");
        EXPECT_EQ(errors, 0);
    }
}
