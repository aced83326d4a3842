#include "spectral/dielectric.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>

namespace metamer {

double RefractiveIndex::at(double wavelength_nm) const {
    const double um = wavelength_nm * 1e-3, um2 = um * um;
    switch (kind) {
        case Kind::Constant: return constant;
        case Kind::Table: {
            if (values.empty() || values.size() != wavelengths_nm.size())
                failRuntime("a refractive-index table needs as many values as wavelengths");
            if (wavelength_nm <= wavelengths_nm.front()) return values.front();
            if (wavelength_nm >= wavelengths_nm.back()) return values.back();
            const size_t i = size_t(std::upper_bound(wavelengths_nm.begin(), wavelengths_nm.end(), wavelength_nm) -
                                    wavelengths_nm.begin());
            const double t = (wavelength_nm - wavelengths_nm[i - 1]) / (wavelengths_nm[i] - wavelengths_nm[i - 1]);
            return values[i - 1] + t * (values[i] - values[i - 1]);
        }
        case Kind::Sellmeier: {
            double n2 = 1.0;
            for (size_t k = 0; k < b.size() && k < c.size(); ++k) n2 += b[k] * um2 / (um2 - c[k]);
            return std::sqrt(n2);
        }
        case Kind::Cauchy: {
            const double a = b.size() > 0 ? b[0] : 1.0, bb = b.size() > 1 ? b[1] : 0.0, cc = b.size() > 2 ? b[2] : 0.0;
            return a + bb / um2 + cc / (um2 * um2);
        }
    }
    return constant;
}

RefractiveIndex nbk7() {
    RefractiveIndex n;
    n.kind = RefractiveIndex::Kind::Sellmeier;
    n.b = {1.03961212, 0.231792344, 1.01046945};
    n.c = {0.00600069867, 0.0200179144, 103.560653};
    return n;
}

double abbeNumber(const RefractiveIndex& n) {
    return (n.at(587.5618) - 1.0) / (n.at(486.1327) - n.at(656.2725));
}

double refractedCosine(double n1, double n2, double cosI) {
    const double sinI2 = std::max(0.0, 1.0 - cosI * cosI);
    const double sinT2 = (n1 / n2) * (n1 / n2) * sinI2;
    return sinT2 >= 1.0 ? 0.0 : std::sqrt(1.0 - sinT2);
}

FresnelReflectance fresnelReflectance(double n1, double n2, double cosI) {
    const double cosT = refractedCosine(n1, n2, cosI);
    FresnelReflectance r;
    if (cosT == 0.0) {
        r.s = r.p = 1.0;
        r.total = true;
        return r;
    }
    const double rs = (n1 * cosI - n2 * cosT) / (n1 * cosI + n2 * cosT);
    const double rp = (n1 * cosT - n2 * cosI) / (n1 * cosT + n2 * cosI);
    r.s = rs * rs;
    r.p = rp * rp;
    return r;
}

SlabReflectanceTransmittance slab(double n, double cosIncidence, double tau) {
    const FresnelReflectance f = fresnelReflectance(1.0, n, cosIncidence);
    SlabReflectanceTransmittance out;
    for (const double r : {f.s, f.p}) {
        const double denominator = 1.0 - r * r * tau * tau;
        out.reflectance += 0.5 * (r + (1.0 - r) * (1.0 - r) * r * tau * tau / denominator);
        out.transmittance += 0.5 * (1.0 - r) * (1.0 - r) * tau / denominator;
    }
    return out;
}

double slabInternalTransmittance(double n, double cosIncidence, double absorbancePerMetre, double thickness_m) {
    const double cosT = refractedCosine(1.0, n, cosIncidence);
    return beerLambert(absorbancePerMetre, thickness_m / cosT);
}

double beerLambert(double absorbancePerMetre, double path_m) { return std::pow(10.0, -absorbancePerMetre * path_m); }

}  // namespace metamer
