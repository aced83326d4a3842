// The test binary's main: googletest, plus one Vulkan context shared by every GPU test (creating
// an instance and device costs ~100 ms). Validation is always on here; when the context is
// destroyed at the end, the layers report leaked objects as errors, which fail the run.
#include "support/gpu.h"

#include <memory>

namespace metamer::test {

namespace {
std::unique_ptr<vk::Context> gContext;
}

vk::Context& gpu() {
    if (!gContext) {
        vk::ContextOptions o = vk::contextOptionsFromEnvironment();
        o.validation = true;
        gContext = std::make_unique<vk::Context>(o);
    }
    return *gContext;
}

class VulkanEnvironment : public ::testing::Environment {
public:
    void TearDown() override {
        if (!gContext) return;
        gContext.reset();
        EXPECT_EQ(vk::Context::validationErrorsAtExit(), 0u)
            << "Vulkan validation reported errors during the run or leaks at device destruction";
    }
};

}  // namespace metamer::test

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    ::testing::AddGlobalTestEnvironment(new metamer::test::VulkanEnvironment);
    return RUN_ALL_TESTS();
}
