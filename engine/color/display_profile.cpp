#include "color/display_profile.h"

#include "core/error.h"

#include <glm/matrix.hpp>
#include <lcms2.h>

#include <cmath>
#include <memory>

namespace metamer {

namespace {

template <typename T, void (*Free)(T*)>
struct Freer {
    void operator()(T* p) const { Free(p); }
};
void closeProfile(void* p) { cmsCloseProfile(p); }
using Profile = std::unique_ptr<void, Freer<void, closeProfile>>;
using Curve = std::unique_ptr<cmsToneCurve, Freer<cmsToneCurve, cmsFreeToneCurve>>;
void freeMlu(cmsMLU* m) { cmsMLUfree(m); }
using Mlu = std::unique_ptr<cmsMLU, Freer<cmsMLU, freeMlu>>;

cmsCIExyY xyYOf(const glm::dvec3& xyz) {
    const double sum = xyz.x + xyz.y + xyz.z;
    return {xyz.x / sum, xyz.y / sum, 1.0};
}

[[noreturn]] void failProfile(const char* what) { failRuntime("cannot build the display's ICC profile: Little CMS could not {}", what); }

}  // namespace

std::vector<uint8_t> displayIccProfile(const DisplayModel& display, const std::string& description) {
    // The black as a per-channel offset of linear RGB; what each channel's curve adds at zero drive.
    const glm::dvec3 k = glm::inverse(display.rgbToXyz) * display.blackXyz;
    glm::dmat3 full = display.rgbToXyz;  // M′: each column the XYZ of one channel at full drive
    Curve curves[3];
    for (int c = 0; c < 3; ++c) {
        full[c] *= 1.0 + k[c];
        cmsToneCurve* curve = nullptr;
        if (display.kind == DisplayKind::Srgb) {
            // IEC 61966-2-1 (lcms type 4): (a·d + b)^γ above d = 0.04045, d/12.92 below.
            const cmsFloat64Number p[5] = {2.4, 1.0 / 1.055, 0.055 / 1.055, 1.0 / 12.92, 0.04045};
            curve = cmsBuildParametricToneCurve(nullptr, 4, p);
        } else {
            // GOG with the black: (R(d) + k)/(1 + k) = (a·d + b)^γ + c, the 1/(1 + k) taken into a and b.
            const double s = 1.0 / (1.0 + k[c]), scale = std::pow(s, 1.0 / display.gamma[c]);
            const cmsFloat64Number p[4] = {display.gamma[c], display.gain[c] * scale, display.offset[c] * scale, k[c] * s};
            curve = cmsBuildParametricToneCurve(nullptr, 3, p);
        }
        if (!curve) failProfile("build a tone curve");
        curves[c].reset(curve);
    }
    const cmsCIExyY white = xyYOf(full * glm::dvec3(1.0));
    const cmsCIExyYTRIPLE primaries = {xyYOf(full[0]), xyYOf(full[1]), xyYOf(full[2])};
    cmsToneCurve* trc[3] = {curves[0].get(), curves[1].get(), curves[2].get()};
    Profile profile(cmsCreateRGBProfile(&white, &primaries, trc));
    if (!profile) failProfile("make an RGB profile");
    Mlu text(cmsMLUalloc(nullptr, 1));
    if (!text || !cmsMLUsetASCII(text.get(), "en", "US", description.c_str()) ||
        !cmsWriteTag(profile.get(), cmsSigProfileDescriptionTag, text.get()))
        failProfile("write the profile's description");
    Mlu copyright(cmsMLUalloc(nullptr, 1));
    if (!copyright || !cmsMLUsetASCII(copyright.get(), "en", "US", "No copyright, use freely") ||
        !cmsWriteTag(profile.get(), cmsSigCopyrightTag, copyright.get()))
        failProfile("write the profile's copyright");
    cmsSetDeviceClass(profile.get(), cmsSigDisplayClass);
    cmsUInt32Number size = 0;
    if (!cmsSaveProfileToMem(profile.get(), nullptr, &size) || size == 0) failProfile("size the profile");
    std::vector<uint8_t> bytes(size);
    if (!cmsSaveProfileToMem(profile.get(), bytes.data(), &size)) failProfile("write the profile");
    bytes.resize(size);
    // Little CMS stamps the header with the time of writing (dateTimeNumber, bytes 24–35); a fixed
    // date makes the profile a function of the model alone, so a render's PNG is the same bytes
    // every time (no profile ID is computed, so nothing else depends on the date).
    if (bytes.size() >= 36)
        for (int i = 0; i < 6; ++i) {
            bytes[size_t(24 + 2 * i)] = uint8_t(kProfileDate[i] >> 8);
            bytes[size_t(25 + 2 * i)] = uint8_t(kProfileDate[i] & 0xff);
        }
    return bytes;
}

DisplayColourTag displayColourTag(const DisplayModel& display) {
    DisplayColourTag tag;
    if (display.kind == DisplayKind::Srgb)
        tag.srgbChunk = true;
    else
        tag.iccProfile =
            displayIccProfile(display, "Metamer display: " + display.name + " (gain-offset-gamma model, docs/color.md)");
    return tag;
}

}  // namespace metamer
