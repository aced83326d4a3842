// The Vulkan context shared by every GPU test, with validation on. Created on first use; at the
// end of the run it is destroyed and any validation error it reported — leaks included — fails
// the run (see test_main.cpp).
#pragma once

#include "vk/context.h"

#include <gtest/gtest.h>

namespace metamer::test {

vk::Context& gpu();

// Fails the current test if the context reported validation errors since `before`.
#define EXPECT_NO_VALIDATION_ERRORS(before) \
    EXPECT_EQ(::metamer::test::gpu().validationErrors(), (before)) << "Vulkan validation errors (see stderr)"

}  // namespace metamer::test
