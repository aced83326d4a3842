#include "render/display_colour_space.h"

#include "color/display_profile.h"

namespace metamer {

void tagDisplayColourSpace(ImageFile& image, const DisplayModel& display) {
    if (display.kind == DisplayKind::Srgb)
        image.attributes.push_back({"oiio:ColorSpace", "sRGB"});
    else
        image.iccProfile =
            displayIccProfile(display, "Metamer display: " + display.name + " (gain-offset-gamma model, docs/color.md)");
}

}  // namespace metamer
