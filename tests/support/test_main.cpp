// The test binary's main: googletest, plus one Vulkan context shared by every GPU test (creating
// a lavapipe instance and device costs ~100 ms; the layers check the whole run for leaks when the
// context is destroyed at exit).
#include <gtest/gtest.h>

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
