#include "core/memory_limits.h"

#include <gtest/gtest.h>

using namespace metamer;

TEST(MemoryLimits, TheDecodeLimitIsAQuarterOfTheMachine) {
    EXPECT_GT(machineMemoryBytes(), uint64_t(256) << 20);
    EXPECT_EQ(decodedImageLimitBytes(), machineMemoryBytes() / 4);
    EXPECT_EQ(memorySize(uint64_t(3) << 29), "1.5 GiB");
    EXPECT_EQ(memorySize(uint64_t(300) << 20), "300.0 MiB");
}

TEST(MemoryLimits, HostileSizesDoNotWrapAround) {
    requireDecodableSize(1024, 1024, 89, 4, 0, Where{"a.exr"}, "the image");  // 356 MiB: fine anywhere
    // 2^31 × 2^31 × 2^31 × 4 wraps a 64-bit product to 0; the check must still refuse it.
    try {
        requireDecodableSize(uint64_t(1) << 31, uint64_t(1) << 31, uint64_t(1) << 31, 4, 0, Where{"a.exr"},
                             "the image");
        FAIL() << "not refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(e.text().find("a.exr: the image is 2147483648×2147483648 with 2147483648 channels: decoded it "
                                "would take 3.96e+28 bytes"), std::string::npos) << e.text();
    }
}
