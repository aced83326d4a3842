#include "scene/gltf_material.h"

#include <algorithm>
#include <cmath>

namespace metamer {

double glossFromRoughness(double roughness) {
    double a = roughness * roughness;
    if (!(a > 0.0)) return kMaxGltfGloss;
    return std::clamp(2.0 / (a * a) - 2.0, 0.0, kMaxGltfGloss);
}

Spectrum upsampledSpectrum(const RgbUpsampler& up, const glm::dvec3& linearRgb, double scale) {
    RgbUpsampler::Coefficients c = up.fit(linearRgb);
    Spectrum s;
    for (double l = 200.0; l <= 2500.0 + 1e-9; l += 5.0) {
        s.wavelengths_nm.push_back(l);
        s.values.push_back(scale * RgbUpsampler::reflectance(c, l));
    }
    return s;
}

Material materialFromGltf(const GltfMaterial& g, const RgbUpsampler& up, const Where& where) {
    Material m;
    m.name = g.name;
    glm::dvec3 base(g.baseColorFactor);
    m.diffuse.kind = m.specular.kind = SpectrumKind::Reflectance;
    m.diffuse.where = where.child("diffuse");
    m.specular.where = where.child("specular");
    const double dielectric = 1.0 - g.metallic;
    // With a base colour texture the factor is folded into the texels (the loader does it), so
    // the spectrum is only the dielectric share.
    if (g.baseColorTexture)
        m.diffuse.spectrum = Spectrum::makeConstant(dielectric);
    else
        m.diffuse.spectrum = dielectric > 0.0 ? upsampledSpectrum(up, base, dielectric) : Spectrum::makeConstant(0.0);
    m.diffuse.spectrum.source = fmt::format("glTF '{}' baseColor", g.name);
    glm::dvec3 f0 = glm::mix(glm::dvec3(0.04), base, g.metallic);
    m.specular.spectrum = upsampledSpectrum(up, f0);
    m.specular.spectrum.source = fmt::format("glTF '{}' F0", g.name);
    m.gloss = glossFromRoughness(g.roughness);
    return m;
}

}  // namespace metamer
