// Writes up-sampled spectra for tests/python/check_upsampling_colour.py: one line per colour with
// the linear sRGB input, the fitted coefficients (nm units), what the engine computes for the
// spectrum's colour (linear sRGB under D65) and ρ at 1 nm over 360–830 nm.
// Usage: write_upsampled_spectra OUT.csv
#include "core/error.h"
#include "color/rgb_upsampling.h"

#include <cstdio>
#include <random>
#include <vector>

int main(int argc, char** argv) {
    using namespace metamer;
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUT.csv\n", argv[0]);
        return 2;
    }
    try {
        const SpectrumLibrary library;
        const RgbUpsampler& up = RgbUpsampler::srgb(library);
        std::vector<glm::dvec3> colours;
        for (int r = 0; r <= 2; ++r)  // the cube's corners, edge and face centres, greys
            for (int g = 0; g <= 2; ++g)
                for (int b = 0; b <= 2; ++b) colours.emplace_back(r / 2.0, g / 2.0, b / 2.0);
        for (double v : {0.001, 0.05, 0.18, 0.9}) colours.emplace_back(v, v, v);
        for (const glm::dvec3& e : {glm::dvec3(254, 255, 255), glm::dvec3(1, 0, 0), glm::dvec3(250, 20, 3)})
            colours.push_back(RgbUpsampler::decodeSrgb(e / 255.0));
        std::mt19937 rng(1999);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        for (int i = 0; i < 40; ++i) colours.emplace_back(u(rng), u(rng), u(rng));

        std::FILE* out = std::fopen(argv[1], "w");
        if (!out) failRuntime("cannot write {}", argv[1]);
        std::fprintf(out, "r,g,b,c0,c1,c2,engine_r,engine_g,engine_b");
        for (int nm = 360; nm <= 830; ++nm) std::fprintf(out, ",rho_%d", nm);
        std::fprintf(out, "\n");
        for (const glm::dvec3& c : colours) {
            const RgbUpsampler::Coefficients f = up.fit(c);
            const glm::dvec3 rgb = up.linearRgbOf(f);
            std::fprintf(out, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", c.x, c.y, c.z, f.c0, f.c1, f.c2,
                         rgb.x, rgb.y, rgb.z);
            for (int nm = 360; nm <= 830; ++nm) std::fprintf(out, ",%.17g", RgbUpsampler::reflectance(f, nm));
            std::fprintf(out, "\n");
        }
        if (std::fclose(out) != 0) failRuntime("cannot write {}", argv[1]);
    } catch (const Error& e) {
        std::fprintf(stderr, "write_upsampled_spectra: %s\n", e.what());
        return 1;
    }
    return 0;
}
