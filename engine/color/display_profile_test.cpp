// The displays' ICC profiles (color/display_profile) read back by Little CMS: the primaries and
// white are the model's (undoing the profile's D50 adaptation, its `chad` tag), and the profile's
// transform of counts to XYZ is the model's decodeCounts, black level included.
#include "color/display_profile.h"

#include "color/display_rgb.h"

#include <gtest/gtest.h>
#include <lcms2.h>

#include <ctime>

#include <glm/matrix.hpp>

using namespace metamer;

namespace {

// The chad tag as Little CMS returns it: 9 doubles, row by row (glm takes columns).
glm::dmat3 matrixOf(const cmsFloat64Number* m) {
    glm::dmat3 out;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) out[c][r] = m[3 * r + c];
    return out;
}

glm::dvec3 xyzTag(cmsHPROFILE profile, cmsTagSignature tag) {
    const auto* v = static_cast<const cmsCIEXYZ*>(cmsReadTag(profile, tag));
    return v ? glm::dvec3(v->X, v->Y, v->Z) : glm::dvec3(0.0);
}

glm::dvec2 xy(const glm::dvec3& v) { return glm::dvec2(v.x, v.y) / (v.x + v.y + v.z); }

}  // namespace

TEST(DisplayProfile, LittleCmsReadsTheModelsPrimariesWhiteAndCurves) {
    for (const char* name : {"crt", "srgb"}) {
        SCOPED_TRACE(name);
        const DisplayModel display = parseDisplay(name, 8, Where{});
        const std::vector<uint8_t> bytes = displayIccProfile(display, std::string("test ") + name);
        cmsHPROFILE profile = cmsOpenProfileFromMem(bytes.data(), cmsUInt32Number(bytes.size()));
        ASSERT_TRUE(profile);
        EXPECT_EQ(cmsGetDeviceClass(profile), cmsSigDisplayClass);
        EXPECT_EQ(cmsGetColorSpace(profile), cmsSigRgbData);
        EXPECT_EQ(cmsGetPCS(profile), cmsSigXYZData);
        char text[64] = {};
        cmsGetProfileInfoASCII(profile, cmsInfoDescription, "en", "US", text, sizeof text);
        EXPECT_EQ(std::string(text), std::string("test ") + name);

        // The colorants are stored adapted to D50; the chad tag undoes that.
        const auto* chad = static_cast<const cmsFloat64Number*>(cmsReadTag(profile, cmsSigChromaticAdaptationTag));
        ASSERT_TRUE(chad);
        const glm::dmat3 toNative = glm::inverse(matrixOf(chad));
        const DisplayPrimaries p = displayPrimaries(display);
        const glm::dvec2 expected[3] = {p.red, p.green, p.blue};
        const cmsTagSignature tags[3] = {cmsSigRedColorantTag, cmsSigGreenColorantTag, cmsSigBlueColorantTag};
        for (int c = 0; c < 3; ++c) {
            const glm::dvec2 got = xy(toNative * xyzTag(profile, tags[c]));
            EXPECT_NEAR(got.x, expected[c].x, 2e-4) << c;
            EXPECT_NEAR(got.y, expected[c].y, 2e-4) << c;
        }
        const glm::dvec2 white = xy(toNative * (xyzTag(profile, tags[0]) + xyzTag(profile, tags[1]) + xyzTag(profile, tags[2])));
        const glm::dvec2 modelWhite = xy(display.whiteXyz);
        EXPECT_NEAR(white.x, modelWhite.x, 2e-4);
        EXPECT_NEAR(white.y, modelWhite.y, 2e-4);

        // Counts → PCS XYZ through lcms (relative colorimetric: white → D50, Y = 1), back to the
        // display's own white: the model's decodeCounts, black level included.
        cmsHPROFILE xyzProfile = cmsCreateXYZProfile();
        cmsHTRANSFORM t = cmsCreateTransform(profile, TYPE_RGB_DBL, xyzProfile, TYPE_XYZ_DBL,
                                             INTENT_RELATIVE_COLORIMETRIC, cmsFLAGS_NOOPTIMIZE | cmsFLAGS_NOCACHE);
        ASSERT_TRUE(t);
        for (const glm::dvec3 counts : {glm::dvec3(0), glm::dvec3(3), glm::dvec3(255), glm::dvec3(255, 0, 0),
                                        glm::dvec3(0, 128, 0), glm::dvec3(20, 90, 200), glm::dvec3(6, 6, 6)}) {
            const double in[3] = {counts.x / 255.0, counts.y / 255.0, counts.z / 255.0};
            double pcs[3] = {};
            cmsDoTransform(t, in, pcs, 1);
            const glm::dvec3 got = toNative * glm::dvec3(pcs[0], pcs[1], pcs[2]);
            const glm::dvec3 want = decodeCounts(display, counts);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(got[c], want[c], 5e-4) << "counts " << counts.x << "," << counts.y << "," << counts.z << " [" << c << "]";
        }
        cmsDeleteTransform(t);
        cmsCloseProfile(xyzProfile);
        cmsCloseProfile(profile);
    }
}

// The same model gives the same bytes (a render's PNG is reproducible): the header's date is fixed,
// not the time of writing, and Little CMS reads it back.
TEST(DisplayProfile, TheSameModelGivesTheSameBytesWithAFixedDate) {
    const DisplayModel display = parseDisplay("crt", 8, Where{});
    const std::vector<uint8_t> bytes = displayIccProfile(display, "test crt");
    cmsHPROFILE profile = cmsOpenProfileFromMem(bytes.data(), cmsUInt32Number(bytes.size()));
    ASSERT_TRUE(profile);
    struct tm date {};
    ASSERT_TRUE(cmsGetHeaderCreationDateTime(profile, &date));
    cmsCloseProfile(profile);
    EXPECT_EQ(date.tm_year + 1900, kProfileDate[0]);
    EXPECT_EQ(date.tm_mon + 1, kProfileDate[1]);
    EXPECT_EQ(date.tm_mday, kProfileDate[2]);
    EXPECT_EQ(date.tm_hour, kProfileDate[3]);
    EXPECT_EQ(displayIccProfile(display, "test crt"), bytes);
}
