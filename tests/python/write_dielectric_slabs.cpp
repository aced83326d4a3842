// Writes slabs' reflectance and transmittance as engine/spectral/dielectric computes them, for
// tests/python/check_dielectric_tmm.py to compare with the `tmm` package's incoherent solver: one
// line per case — n, wavelength (nm), incidence (degrees), thickness (m), decadic absorbance (per
// metre), R, T. Cases: n = 1.5 and N-BK7 (Sellmeier, at 400–700 nm), 0–85°, clear and absorbing.
// Usage: write_dielectric_slabs OUT.csv
#include "spectral/dielectric.h"

#include <cmath>
#include <cstdio>
#include <numbers>

int main(int argc, char** argv) {
    using namespace metamer;
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUT.csv\n", argv[0]);
        return 2;
    }
    std::FILE* f = std::fopen(argv[1], "w");
    if (!f) {
        std::perror(argv[1]);
        return 1;
    }
    std::fprintf(f, "n,wavelength_nm,incidence_deg,thickness_m,absorbance_per_m,R,T\n");
    const RefractiveIndex glass = nbk7();
    for (double nm : {400.0, 486.1327, 550.0, 587.5618, 656.2725, 700.0})
        for (bool bk7 : {false, true})
            for (double degrees : {0.0, 30.0, 60.0, 85.0})
                for (double absorbance : {0.0, 20.0, 200.0}) {
                    const double n = bk7 ? glass.at(nm) : 1.5, d = 0.005;
                    const double cosI = std::cos(degrees * std::numbers::pi / 180.0);
                    const SlabReflectanceTransmittance s = slab(n, cosI, slabInternalTransmittance(n, cosI, absorbance, d));
                    std::fprintf(f, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", n, nm, degrees, d, absorbance,
                                 s.reflectance, s.transmittance);
                }
    return std::fclose(f) == 0 ? 0 : 1;
}
