#include "render/quicklook_png.h"

#include "color/quick_look.h"
#include "io/image_file.h"

namespace metamer {

QuickLookReport writeQuickLookPng(const std::filesystem::path& path, const SpectralCube& cube,
                                  const SpectrumLibrary& library) {
    QuickLook q;
    try {
        q = quickLook(cube, library);
    } catch (const Error& e) {
        failRuntime("cannot write '{}': {}", path.string(), e.message());
    }
    QuickLookReport report{q.yPercentile99, q.yScale, q.clippedPixels, q.nonFinitePixels, q.description};
    ImageFile file{cube.width, cube.height, {"R", "G", "B"},
                   {{"ImageDescription", report.description}, {"oiio:ColorSpace", "sRGB"}}};
    writeImage(path, file, q.counts, 8);
    return report;
}

}  // namespace metamer
