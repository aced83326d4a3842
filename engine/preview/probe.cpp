#include "preview/probe.h"

#include "color/lab.h"

#include <fmt/format.h>

namespace metamer::preview {

ProbeReadout probePixel(const TonemapPlan& plan, const Representation& representation, const float* values,
                        const Grid& grid, const DisplayImage& image, int x, int y) {
    ProbeReadout p;
    if (x < 0 || y < 0 || x >= image.width || y >= image.height)
        failRuntime("probe at {},{} is outside the {}×{} image", x, y, image.width, image.height);
    p.x = x;
    p.y = y;
    const float* px = values;
    const int n = grid.bands();
    p.values.assign(px, px + n);
    if (representation.mode.spectral()) {
        for (int b = 0; b < n; ++b) p.wavelengths_nm.push_back(grid.wavelength(b));
        if (representation.mode.kind == ModeKind::Linear) {
            // As `metamer render` writes a linear:K cube: the pixel projected onto the basis.
            std::vector<double> bands(px, px + n);
            std::vector<double> projected = project(representation, bands);
            for (int b = 0; b < n; ++b) p.values[b] = float(projected[b]);
        }
    } else {
        p.channelNames = representation.channelNames;
    }
    p.responses.assign(plan.detector.weights.size(), 0.0);
    glm::dvec3 rel = relativeXyz(plan, px, p.responses.data());
    p.colorimetric = plan.mode != TonemapMode::ResponsesOnly;
    if (p.colorimetric) {
        p.xyz = rel * 100.0;
        p.whiteXyz = plan.sourceWhiteXyz * 100.0;  // Y = 100 for observers and cameras
        p.lab = xyzToLab(p.xyz, p.whiteXyz);
    }
    p.bits = plan.display.bits;
    if (!image.counts.empty()) {
        size_t i = size_t(y) * image.width + x;
        p.counts = glm::ivec3(image.counts[3 * i], image.counts[3 * i + 1], image.counts[3 * i + 2]);
        p.clipped = !image.clipped.empty() && image.clipped[i];
    }
    return p;
}

std::string describeProbe(const ProbeReadout& p) {
    std::string s = fmt::format("probe {},{}:", p.x, p.y);
    if (p.colorimetric)
        s += fmt::format(" XYZ {:.3f} {:.3f} {:.3f} (white Y = 100)  L*a*b* {:.3f} {:.3f} {:.3f}", p.xyz.x, p.xyz.y,
                         p.xyz.z, p.lab.x, p.lab.y, p.lab.z);
    s += fmt::format("  counts {} {} {} ({} bits{})", p.counts.x, p.counts.y, p.counts.z, p.bits,
                     p.clipped ? ", clipped" : "");
    // The peak of the spectrum (or the largest channel), for a quick look in logs.
    size_t peak = 0;
    for (size_t b = 1; b < p.values.size(); ++b)
        if (p.values[b] > p.values[peak]) peak = b;
    if (!p.values.empty()) {
        if (!p.wavelengths_nm.empty())
            s += fmt::format("  peak {:.4g} W·sr⁻¹·m⁻²·nm⁻¹ at {:g} nm", p.values[peak], p.wavelengths_nm[peak]);
        else
            s += fmt::format("  largest channel {} = {:.4g}", peak < p.channelNames.size() ? p.channelNames[peak] : "?",
                             p.values[peak]);
    }
    return s;
}

}  // namespace metamer::preview
