#include "isp/camera_metrics.h"

#include "color/delta_e.h"
#include "color/lab.h"
#include "color/srgb.h"

#include <glm/glm.hpp>

#include <cmath>

namespace metamer {

void requireRectInside(const PixelRect& r, int width, int height, const Where& where) {
    if (r[0] < 0 || r[1] < 0 || r[2] < 1 || r[3] < 1 || r[0] > width - r[2] || r[1] > height - r[3])
        failInput(where, "the rectangle [{}, {}, {}, {}] (x, y, width, height) is not inside the {}×{} frame", r[0], r[1],
                  r[2], r[3], width, height);
}

DevelopedColourError developedColourError(const std::vector<glm::dvec3>& developed, const std::vector<glm::dvec3>& reference,
                                          const glm::dvec3& referenceWhite, Adaptation adaptation, size_t exposureFrom,
                                          const Where& where) {
    if (developed.size() != reference.size() || developed.empty())
        failInput(where, "expected as many developed colours as reference colours, at least one; got {} and {}",
                  developed.size(), reference.size());
    if (exposureFrom >= developed.size())
        failInput(where, "the exposure is set by colour {}; there are {}", exposureFrom, developed.size());
    if (!(referenceWhite.y > 0.0) || !std::isfinite(referenceWhite.x + referenceWhite.y + referenceWhite.z))
        failInput(where, "the reference white has no luminance (Y = {:g})", referenceWhite.y);
    const glm::dmat3 toXyz = glm::inverse(xyzToLinearSrgbMatrix());
    const glm::dmat3 cat = adaptationMatrix(adaptation, referenceWhite / referenceWhite.y, kD65WhiteXyz);
    std::vector<glm::dvec3> dev, ref;
    for (size_t i = 0; i < developed.size(); ++i) {
        dev.push_back(toXyz * developed[i]);
        ref.push_back(cat * (reference[i] / referenceWhite.y));
    }
    if (!(dev[exposureFrom].y > 0.0))
        failInput(where, "developed colour {} (which sets the exposure) has no luminance", exposureFrom);
    DevelopedColourError out;
    out.exposureScale = ref[exposureFrom].y / dev[exposureFrom].y;
    for (size_t i = 0; i < dev.size(); ++i) {
        const glm::dvec3 a = xyzToLab(dev[i] * out.exposureScale, kD65WhiteXyz), b = xyzToLab(ref[i], kD65WhiteXyz);
        out.developedLab.push_back(a);
        out.referenceLab.push_back(b);
        out.deltaE2000.push_back(deltaE2000(a, b));
    }
    return out;
}

}  // namespace metamer
