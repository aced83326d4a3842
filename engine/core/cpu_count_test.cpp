#include "core/cpu_count.h"

#include "core/error.h"

#include <gtest/gtest.h>

using namespace metamer;

TEST(CpuCount, TheFlagWinsOverSlurmAndAffinity) {
    const CpuCount c = chooseCpuCount(3, "8", 16);
    EXPECT_EQ(c.threads, 3);
    EXPECT_EQ(c.source, "--threads");
}

TEST(CpuCount, SlurmIsBoundedByTheAffinityMask) {
    EXPECT_EQ(chooseCpuCount(std::nullopt, "4", 16).threads, 4);
    const CpuCount bounded = chooseCpuCount(std::nullopt, "64", 2);
    EXPECT_EQ(bounded.threads, 2);
    EXPECT_NE(bounded.source.find("SLURM_CPUS_PER_TASK=64"), std::string::npos) << bounded.source;
}

TEST(CpuCount, WithoutEitherTheAffinityCount) {
    EXPECT_EQ(chooseCpuCount(std::nullopt, nullptr, 5).threads, 5);
    EXPECT_EQ(chooseCpuCount(std::nullopt, "", 5).threads, 5);  // set but empty: as unset
    EXPECT_GE(affinityCpuCount(), 1);
}

TEST(CpuCount, BadValuesNameTheirSource) {
    try {
        chooseCpuCount(std::nullopt, "four", 2);
        FAIL() << "accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(e.text().find("SLURM_CPUS_PER_TASK: 'four' is not a thread count"), std::string::npos) << e.text();
    }
    try {
        chooseCpuCount(0, nullptr, 2);
        FAIL() << "accepted";
    } catch (const Error& e) {
        EXPECT_NE(e.text().find("--threads"), std::string::npos) << e.text();
    }
}
