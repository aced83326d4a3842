#include "render/display_colour_space.h"

#include "color/display_profile.h"

namespace metamer {

void tagDisplayColourSpace(ImageFile& image, const DisplayModel& display) {
    DisplayColourTag tag = displayColourTag(display);
    if (tag.srgbChunk) image.attributes.push_back({"oiio:ColorSpace", "sRGB"});
    image.iccProfile = std::move(tag.iccProfile);
}

}  // namespace metamer
