#include "preview/display_bytes.h"

#include <gtest/gtest.h>

using namespace metamer;
using namespace metamer::preview;

TEST(DisplayBytes, SixteenBitCountsRoundToTheNearestEightBitCount) {
    EXPECT_EQ(windowCount(0, 16), 0);
    EXPECT_EQ(windowCount(65535, 16), 255);
    EXPECT_EQ(windowCount(257 * 128, 16), 128);  // exact: 257 · c ↔ c
    EXPECT_EQ(windowCount(128, 16), 0);          // 0.498 of a count
    EXPECT_EQ(windowCount(129, 16), 1);          // 0.502 of a count
    for (int c = 0; c < 256; ++c) EXPECT_EQ(windowCount(uint16_t(c), 8), c);
}

TEST(DisplayBytes, ChannelOrderFollowsTheSwapchainAndRoundTrips) {
    DisplayImage img;
    img.width = 2;
    img.height = 1;
    img.counts = {10, 20, 30, 40, 50, 60};
    std::vector<uint8_t> bgra = toWindowBytes(img, 8, true), rgba = toWindowBytes(img, 8, false);
    EXPECT_EQ(bgra, (std::vector<uint8_t>{30, 20, 10, 255, 60, 50, 40, 255}));
    EXPECT_EQ(rgba, (std::vector<uint8_t>{10, 20, 30, 255, 40, 50, 60, 255}));
    EXPECT_EQ(fromWindowBytes(bgra, 2, 1, true, 0, 0, 2, 1), img.counts);
    EXPECT_EQ(fromWindowBytes(rgba, 2, 1, false, 1, 0, 1, 1), (std::vector<uint16_t>{40, 50, 60}));
    EXPECT_THROW(fromWindowBytes(rgba, 2, 1, false, 1, 0, 2, 1), Error);  // outside the frame
}
