#include "spectral/grid.h"

#include <gtest/gtest.h>

using namespace metamer;

TEST(Grid, DefaultIs89BandsIn23Layers) {
    Grid g;
    EXPECT_EQ(g.bands(), 89);
    EXPECT_EQ(g.layers(), 23);
    EXPECT_DOUBLE_EQ(g.wavelength(88), 740.0);
}

TEST(Grid, ExtremesWithinLimitsAreValid) {
    EXPECT_EQ(Grid::parse("300:740:0.5", Where{}).bands(), 881);
    EXPECT_EQ(Grid::parse("200:2500:50", Where{}).bands(), 47);
    EXPECT_EQ(Grid::parse("555:555:1", Where{}).bands(), 1);  // a single band
    EXPECT_EQ(Grid::parse("400:700:0.5", Where{}).layers(), 151);
}

TEST(Grid, BadGridsNameTheProblem) {
    auto message = [](const std::string& text) {
        try {
            Grid::parse(text, Where{"", "--grid"});
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadInput);
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(message("300:740:0.25").find("step"), std::string::npos);
    EXPECT_NE(message("300:740:60").find("step"), std::string::npos);
    EXPECT_NE(message("150:740:5").find("outside"), std::string::npos);
    EXPECT_NE(message("300:2600:5").find("outside"), std::string::npos);
    EXPECT_NE(message("740:300:5").find("below"), std::string::npos);
    EXPECT_NE(message("300:742:5").find("whole number"), std::string::npos);
    EXPECT_NE(message("300-740-5").find("START:END:STEP"), std::string::npos);
    EXPECT_NE(message("300:740").find("--grid"), std::string::npos);
    EXPECT_NE(message("300:740:nan").find("--grid"), std::string::npos);
}
