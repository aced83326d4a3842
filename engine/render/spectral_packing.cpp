#include "render/spectral_packing.h"

#include "render/crossing_tables.h"

#include "reference/hemisphere_lobe.h"
#include "reference/lobe_table.h"
#include "spectral/dielectric.h"

#include "lobe_lookup.h"

#include <algorithm>
#include <map>
#include <cmath>
#include <limits>

namespace metamer {

void scatterBands(const std::vector<double>& values, int pass, glm::vec4* dst) {
    for (int k = 0; k < MAX_OUTPUTS; ++k)
        for (int c = 0; c < 4; ++c) {
            size_t b = size_t(pass) * BANDS_PER_PASS + size_t(k) * 4 + c;
            dst[k][c] = b < values.size() ? float(values[b]) : 0.0f;
        }
}

namespace {

// F(λo) of material m under irradiance E: the fluorescent radiance per unit geometric factor,
// (1/π)·Σᵢ D(λᵢ, λo)·E(λᵢ)·Δλ, or for a pair (Φ/π)·ê(λo)/λo·Σᵢ a·E·λᵢ·Δλ; in double.
std::vector<double> fluorescentRadiance(const MaterialOnGrid& m, const std::vector<double>& E, const SceneOnGrid& g) {
    const size_t n = g.wavelengths_nm.size();
    const double step = g.grid.step_nm;
    std::vector<double> out(n, 0.0);
    if (m.isMatrix()) {
        for (size_t in = 0; in < n; ++in) {
            const double e = E[in] * step / M_PI;
            if (e == 0.0) continue;
            const double* row = &m.donaldson[in * n];
            for (size_t o = 0; o < n; ++o) out[o] += row[o] * e;
        }
    } else {
        double absorbed = 0.0;  // Σ a·E·λ·Δλ
        for (size_t b = 0; b < n; ++b) absorbed += m.excitation[b] * E[b] * g.wavelengths_nm[b] * step;
        for (size_t o = 0; o < n; ++o) out[o] = m.quantum_yield / M_PI * m.emission[o] / g.wavelengths_nm[o] * absorbed;
    }
    return out;
}

// The fluorescent radiance per unit geometric factor of every fluorescent material under every
// light, F_l(λo) = (1/π)·Σᵢ D(λᵢ, λo)·E_l(λᵢ)·Δλ, in double, then rounded once to float. The
// rank-one form is the matrix D = Φ·a(λᵢ)·ê(λo)·λᵢ/λo, which factors the sum:
// F_l(λo) = (Φ/π)·ê(λo)/λo·Σᵢ a·E_l·λᵢ·Δλ. F is a radiance (× d² for a point light), so it is no
// nearer float32's limits than the image itself; a value beyond them is refused, as a light is.
void packFluorescence(PackedScene& p, const Scene& scene, const SceneOnGrid& g, const std::vector<size_t>& order,
                      int passes) {
    const size_t n = g.wavelengths_nm.size(), lights = order.size();
    p.lightSlots = std::max<int>(1, int(lights));
    p.fluorescenceRecord.assign(g.materials.size(), 0);
    std::vector<std::vector<double>> emitted;  // per fluorescent material: [light][band]
    for (size_t mi = 0; mi < g.materials.size(); ++mi) {
        const MaterialOnGrid& m = g.materials[mi];
        if (!m.fluorescent || !p.fluorescenceSpectra) continue;
        p.fluorescenceRecord[mi] = uint32_t(emitted.size() + 1);
        std::vector<double> f(lights * n, 0.0);
        for (size_t i = 0; i < lights; ++i) {
            const std::vector<double> radiance = fluorescentRadiance(m, g.lights[order[i]], g);
            double* out = &f[i * n];
            std::copy(radiance.begin(), radiance.end(), out);
            for (size_t o = 0; o < n; ++o)
                if (!(std::fabs(out[o]) <= double(std::numeric_limits<float>::max()))) {
                    const Fluorescence& fl = *scene.materials[mi].fluorescence;
                    failInput(fl.matrix ? fl.matrix->where : fl.excitation.where,
                              "the fluorescence of material '{}' under {} is {:g} W·sr⁻¹·m⁻²·nm⁻¹ per unit geometric "
                              "factor at {:g} nm, beyond the largest float32 ({:g}) the GPU path computes with",
                              scene.materials[mi].name, scene.lights[order[i]].name, out[o], g.wavelengths_nm[o],
                              double(std::numeric_limits<float>::max()));
                }
        }
        emitted.push_back(std::move(f));
    }
    p.fluorescenceRecords = int(emitted.size()) + 1;
    const size_t recordVec4 = size_t(p.lightSlots) * MAX_OUTPUTS;
    if (!p.fluorescenceSpectra) {  // never read: one record of zeros for the binding
        p.fluorescence.assign(recordVec4, glm::vec4(0.0f));
        return;
    }
    p.fluorescence.assign(size_t(passes) * p.fluorescenceRecords * recordVec4, glm::vec4(0.0f));
    std::vector<double> bands(n);
    for (int pass = 0; pass < passes; ++pass)
        for (size_t r = 1; r < size_t(p.fluorescenceRecords); ++r)
            for (size_t i = 0; i < lights; ++i) {
                const double* src = &emitted[r - 1][i * n];
                bands.assign(src, src + n);
                glm::vec4* dst = &p.fluorescence[((size_t(pass) * p.fluorescenceRecords + r) * p.lightSlots + i) * MAX_OUTPUTS];
                scatterBands(bands, pass, dst);
            }
}

// Lights sorted ambient, directional, point, hemisphere (the shader loops over each kind without
// branching), the shadowing ones first within directional and point; counts them into p.
std::vector<size_t> lightOrder(const Scene& scene, PackedScene& p) {
    std::vector<size_t> order;
    for (Light::Type type : {Light::Type::Ambient, Light::Type::Directional, Light::Type::Point, Light::Type::Hemisphere})
        for (bool shadows : {true, false})
            for (size_t l = 0; l < scene.lights.size(); ++l) {
                const Light& light = scene.lights[l];
                if (light.type != type || light.castsShadows() != shadows) continue;
                order.push_back(l);
                (type == Light::Type::Ambient       ? p.ambient
                 : type == Light::Type::Directional ? p.directional
                 : type == Light::Type::Point       ? p.point
                                                    : p.hemisphere)++;
                if (shadows) (type == Light::Type::Directional ? p.shadowedDirectional : p.shadowedPoint)++;
            }
    // Hemisphere lights keep their order, so the reference's pairing holds for them as they are here.
    const std::vector<bool> paired = pairedWithPreviousHemisphere(scene.lights);
    for (int i = 1; i < p.hemisphere && i < 32; ++i)
        if (paired[order[order.size() - size_t(p.hemisphere) + size_t(i)]]) p.hemispherePaired |= 1u << i;
    return order;
}

// The optical-depth channels (interface.h) of the coloured shadows and the camera's channel pass:
// one per sheet and medium, then two per slab, in p.depthSpectra per channel and band layer;
// returns every material's first channel (−1: none). View-independent, once per scene, in double
// rounded once to float.
// A rank-one fluorescent material's ê(λ)/λ (nm⁻², on the grid) with a power of two 2^shift moved
// out of it, for its coupling to take: the coupling is the radiance over ê/λ (~1e-5 nm⁻² for a
// dye), so in float32 it would overflow ~1e5 times sooner than the radiance does (at a light scale
// of ~1e35); moving 2^shift keeps both near the radiance's magnitude and leaves their product the
// same bit for bit. pack() and packResponses() share it, so that their products are the same too.
struct ScaledEmission {
    std::vector<double> overLambda;
    int shift = 0;
};
ScaledEmission scaledEmissionOverLambda(const MaterialOnGrid& m, const SceneOnGrid& g) {
    ScaledEmission e;
    e.overLambda.assign(m.diffuse.size(), 0.0);
    double largest = 0.0;
    for (size_t i = 0; i < m.emission.size() && i < e.overLambda.size(); ++i) {
        e.overLambda[i] = m.emission[i] / g.wavelengths_nm[i];
        largest = std::max(largest, e.overLambda[i]);
    }
    e.shift = largest > 0.0 ? std::ilogb(largest) : 0;
    for (double& v : e.overLambda) v = std::ldexp(v, -e.shift);
    return e;
}

std::vector<float> packDepthChannels(PackedScene& p, const Scene& scene, const SceneOnGrid& g, const LocalFrame& frame) {
    std::vector<float> first(g.materials.size(), -1.0f);
    p.depthSpectra.clear();
    if (scene.hasTransparency()) {
        std::vector<size_t> linear, slabs;
        for (size_t m = 0; m < g.materials.size(); ++m) {
            if (g.materials[m].isFilter() || g.materials[m].isMedium()) linear.push_back(m);
            else if (g.materials[m].isSlab()) slabs.push_back(m);
        }
        const size_t channels = linear.size() + 2 * slabs.size();
        if (p.filteredShadows && channels > MAX_DEPTH_CHANNELS)
            failInput(Where{scene.file.string(), "materials", 0},
                      "{} transparent materials cast coloured shadows ({} sheets and media, one optical-depth channel "
                      "each, and {} slabs, two each: {} channels); at most {}: share materials among the transparent "
                      "objects, or cast shadows from no light (\"shadows\": false)",
                      linear.size() + slabs.size(), linear.size(), slabs.size(), channels, MAX_DEPTH_CHANNELS);
        p.depthChannels = int(linear.size());
        p.slabChannels = int(slabs.size());
        p.depthLayers = int(channels + 3) / 4;
        const size_t bands = g.wavelengths_nm.size();
        // One channel's rows: value(b) for the grid's bands, `padding` past them.
        auto rows = [&](auto value, float padding) {
            for (int j = 0; j < p.bandLayers; ++j) {
                glm::vec4 v(padding);
                for (int c = 0; c < 4; ++c)
                    if (size_t(4 * j + c) < bands) v[c] = float(value(size_t(4 * j + c)));
                p.depthSpectra.push_back(v);
            }
        };
        const double log2of10 = std::log2(10.0);
        for (size_t i = 0; i < linear.size(); ++i) {
            const MaterialOnGrid& m = g.materials[linear[i]];
            first[linear[i]] = float(i);
            // A sheet's log2 T (a black band: 2⁻¹⁴⁹, 0 in float, and finite times a zero weight); a
            // medium's −a·log2(10)·unit per unit of path.
            if (m.isFilter())
                rows([&](size_t b) { return std::max(std::log2(m.transmittance[b]), -149.0); }, 0.0f);
            else
                rows([&](size_t b) { return -m.absorbance[b] * log2of10 * frame.unit_m(); }, 0.0f);
        }
        for (size_t i = 0; i < slabs.size(); ++i) {
            const MaterialOnGrid& m = g.materials[slabs[i]];
            first[slabs[i]] = float(linear.size() + 2 * i);
            // n(λ), air past the grid (T = 1 there); the attenuation across the thickness.
            rows([&](size_t b) { return m.ior[b]; }, 1.0f);
            rows([&](size_t b) { return m.slabAbsorbance.empty() ? 0.0 : m.slabAbsorbance[b] * log2of10 * m.slabThickness; }, 0.0f);
        }
        // A flat slab under a directional light is crossed at one angle: its log2 T there, per layer.
        std::vector<glm::dvec3> slabNormal(slabs.size());
        for (size_t i = 0; i < slabs.size() && i < 32; ++i) {
            bool flat = true, any = false;
            for (const PackedDraw& d : p.draws) {
                if (d.material != slabs[i]) continue;
                for (uint32_t k = 0; k < d.indexCount && flat; ++k) {
                    const float* nv = p.vertices[size_t(int64_t(p.indices[d.firstIndex + k]) + d.vertexOffset)].normal;
                    const glm::dvec3 n(nv[0], nv[1], nv[2]);
                    if (!(glm::length(n) > 0.0)) { flat = false; break; }
                    if (!any) slabNormal[i] = glm::normalize(n), any = true;
                    flat = std::abs(glm::dot(glm::normalize(n), slabNormal[i])) > 1.0 - 1e-12;
                }
            }
            if (flat && any) p.flatSlabs |= 1u << i;
        }
        p.slabLayerRows = int(p.depthSpectra.size());
        for (size_t layer = 0; layer < p.shadowEyes.size(); ++layer)
            for (size_t i = 0; i < slabs.size(); ++i) {
                const MaterialOnGrid& m = g.materials[slabs[i]];
                const glm::vec4 eye = p.shadowEyes[layer];
                const bool directional = eye.w < 0.5f && i < 32 && ((p.flatSlabs >> i) & 1u) != 0u;
                const double cosI = directional ? std::min(1.0, std::abs(glm::dot(glm::normalize(glm::dvec3(eye)), slabNormal[i]))) : 1.0;
                rows([&](size_t b) {
                    if (!directional) return 0.0;
                    const double tau = m.slabAbsorbance.empty() ? 1.0 : slabInternalTransmittance(m.ior[b], cosI, m.slabAbsorbance[b], m.slabThickness);
                    return std::max(std::log2(slab(m.ior[b], cosI, tau).transmittance), -149.0);
                }, 0.0f);
            }
    }
    if (p.depthSpectra.empty()) p.depthSpectra.push_back(glm::vec4(0.0f));
    return first;
}

}  // namespace

uint32_t materialSwitches(const MaterialOnGrid& m, bool specular) {
    return (m.fluorescent ? MATERIAL_FLUORESCENT : 0u) | (specular ? MATERIAL_SPECULAR : 0u) |
           (m.diffuseTexture >= 0 ? MATERIAL_DIFFUSE_TEXTURE : 0u) |
           (m.specularTexture >= 0 ? MATERIAL_SPECULAR_TEXTURE : 0u) | (m.normalTexture >= 0 ? MATERIAL_NORMAL_TEXTURE : 0u) |
           (m.isFilter() ? MATERIAL_FILTER : 0u) | (m.isMedium() ? MATERIAL_MEDIUM : 0u) | (m.isSlab() ? MATERIAL_SLAB : 0u) |
           (m.isEmitter() ? MATERIAL_EMITTER : 0u);
}

PackedScene pack(const Scene& scene, const SceneOnGrid& g, int passes, const LocalFrame& frame,
                 const radiosity::SceneInterreflection* interreflection) {
    checkMeshes(scene);  // the vertex and index arrays below are read as they promise
    PackedScene p;
    std::vector<IndirectVertex> indirect;  // per vertex, with interreflection
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        if (mesh.indices.empty()) continue;
        if (interreflection && !interreflection->meshes[m].elements.triangles.empty()) {
            indirect.resize(p.vertices.size());
            packIndirectMesh(p, indirect, scene, g, frame, m, *interreflection);
            continue;
        }
        PackedDraw d{uint32_t(p.indices.size()), uint32_t(mesh.indices.size()), int32_t(p.vertices.size()), mesh.material};
        d.closed = mesh.closed;
        d.transparent = scene.materials[mesh.material].isTransparent();
        glm::dvec3 lower(INFINITY), upper(-INFINITY);
        for (const glm::dvec3& x : mesh.positions) {
            const glm::dvec3 local = frame.position(x);
            lower = glm::min(lower, local);
            upper = glm::max(upper, local);
        }
        d.lower = glm::vec3(lower);
        d.upper = glm::vec3(upper);
        auto vertex = [&p, &mesh, &frame](uint32_t i, const glm::dvec3& normal) {
            glm::dvec2 uv = mesh.uvs.empty() ? glm::dvec2(0.0) : mesh.uvs[i];
            glm::dvec4 t = mesh.tangents.empty() ? glm::dvec4(0.0) : mesh.tangents[i];
            gpu::SpectralVertex v;
            const glm::dvec3 x = frame.position(mesh.positions[i]);  // in double, then rounded once
            for (int k = 0; k < 3; ++k) v.position[k] = float(x[k]);
            for (int k = 0; k < 3; ++k) v.normal[k] = float(normal[k]);
            for (int k = 0; k < 2; ++k) v.uv[k] = float(uv[k]);
            for (int k = 0; k < 4; ++k) v.tangent[k] = float(t[k]);
            p.vertices.push_back(v);
        };
        // Normals of (nearly) zero length, or none at all, are allowed by the model: the reference
        // then shades with the face normal (docs/physics.md, "Two-sided shading"). A triangle
        // with no usable normal at any corner gets its own three vertices carrying the face
        // normal, computed here in double; spectral.frag falls back to a screen-space face normal
        // only where usable normals cancel, which is less precise (~1e-5 rad).
        const bool hasNormals = mesh.normals.size() == mesh.positions.size();
        auto usable = [&](uint32_t i) { return hasNormals && glm::length(mesh.normals[i]) > 1e-12; };
        for (size_t i = 0; i < mesh.positions.size(); ++i)
            vertex(uint32_t(i), hasNormals ? mesh.normals[i] : glm::dvec3(0.0));
        uint32_t next = uint32_t(mesh.positions.size());
        for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
            const uint32_t* tri = &mesh.indices[t];
            if (usable(tri[0]) || usable(tri[1]) || usable(tri[2])) {
                p.indices.insert(p.indices.end(), tri, tri + 3);
                continue;
            }
            const glm::dvec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]], &c = mesh.positions[tri[2]];
            glm::dvec3 face = glm::cross(b - a, c - a);
            const double len = glm::length(face);
            face = len > 0.0 ? face / len : glm::dvec3(0.0);  // zero area: never rasterized
            for (int k = 0; k < 3; ++k) {
                vertex(tri[k], face);
                p.indices.push_back(next++);
            }
        }
        d.indexCount = uint32_t(p.indices.size()) - d.firstIndex;
        p.draws.push_back(d);
    }
    if (interreflection) {
        indirect.resize(p.vertices.size());
        layOutIndirect(p, indirect, passes);
    }
    // Lights sorted by kind (the shader loops over each kind without branching).
    const std::vector<size_t> order = lightOrder(scene, p);
    p.shadowMaps = planShadowMaps(scene, SHADOW_MAP_SIZE, frame);
    for (size_t k = 0; k < p.shadowMaps.layers.size(); ++k) p.shadowBlock.layers[k] = glm::mat4(p.shadowMaps.layers[k].viewProjection);
    p.shadowEyes.assign(p.shadowMaps.layers.size(), glm::vec4(0.0f));
    for (size_t l = 0; l < scene.lights.size(); ++l) {
        const int first = p.shadowMaps.lights[l].firstLayer;
        if (first < 0) continue;
        const Light& light = scene.lights[l];
        const bool point = light.type == Light::Type::Point;
        const glm::vec4 eye = point ? glm::vec4(glm::vec3(frame.position(light.position)), 1.0f)
                                    : glm::vec4(glm::vec3(glm::normalize(light.direction)), 0.0f);
        for (int k = 0; k < (point ? 6 : 1); ++k) p.shadowEyes[size_t(first + k)] = eye;
    }
    for (size_t i = 0; i < order.size(); ++i) {
        const Light& light = scene.lights[order[i]];
        gpu::GpuLight& out = p.lights.lights[i];
        if (light.type == Light::Type::Directional)
            out.vector = glm::vec4(glm::vec3(-glm::normalize(light.direction)), 0.0f);
        else if (light.type == Light::Type::Point)
            out.vector = glm::vec4(glm::vec3(frame.position(light.position)), float(frame.inverseSquareUnit()));
        else if (light.type == Light::Type::Hemisphere)
            out.vector = glm::vec4(glm::vec3(light.up), 0.0f);
        const ShadowLight& shadow = p.shadowMaps.lights[order[i]];
        out.shadow = glm::vec4(float(shadow.firstLayer), float(shadow.texel), 0.0f, 0.0f);
    }
    // The shader holds E(λ) in float32: beyond its largest value E would become +Inf, and Inf × 0
    // (a black band, a light behind the surface) NaN. Refused rather than rendered wrong.
    for (size_t l = 0; l < scene.lights.size(); ++l)
        for (size_t b = 0; b < g.lights[l].size(); ++b)
            if (std::fabs(g.lights[l][b]) > double(std::numeric_limits<float>::max()))
                failInput(scene.lights[l].spectrum.where,
                          "light spectrum '{}' × scale {:g} is {:g} at {:g} nm, beyond the largest float32 ({:g}) "
                          "the GPU path computes with",
                          scene.lights[l].spectrum.spectrum.source, scene.lights[l].scale, g.lights[l][b],
                          g.wavelengths_nm[b], double(std::numeric_limits<float>::max()));
    p.lightSpectra.resize(passes);
    for (int pass = 0; pass < passes; ++pass)
        for (size_t i = 0; i < order.size(); ++i)
            scatterBands(g.lights[order[i]], pass, &p.lightSpectra[pass].lightBands[i * MAX_OUTPUTS]);
    if (interreflection) packEmitters(p, scene, g, frame, *interreflection);

    // A Donaldson matrix does not factor into a coupling × a shape: a scene with one renders every
    // fluorescent material from per-light spectra; other scenes keep the cheaper rank-one form.
    p.fluorescenceSpectra = std::any_of(g.materials.begin(), g.materials.end(),
                                        [](const MaterialOnGrid& m) { return m.fluorescent && m.isMatrix(); });
    p.materials.resize(size_t(passes) * g.materials.size());
    // The hemisphere lights' lobe tables, built (or read from the cache) once per gloss value.
    std::map<double, float> lobeTableAt;
    auto lobeTable = [&](const MaterialOnGrid& m, bool specular) {
        if (p.hemisphere == 0 || !specular || !(m.gloss > 0.0)) return -1.0f;
        auto [it, added] = lobeTableAt.try_emplace(m.gloss, float(p.lobeTables.size()));
        if (added) {
            // The shader gets a table's first entry as a float, exact below 2²⁴ (62 tables).
            if (p.lobeTables.size() + LOBE_TABLE_UVEC4 > (size_t(1) << 24))
                failInput(Where{scene.file.string(), "materials", 0},
                          "more than {} distinct gloss values among the specular materials under hemisphere lights "
                          "(one lobe table each, docs/physics.md \"Hemisphere lights\")",
                          ((size_t(1) << 24) / LOBE_TABLE_UVEC4));
            const auto table = lobeTableFor(m.gloss);
            p.lobeTables.insert(p.lobeTables.end(), table->data.begin(), table->data.end());
        }
        return it->second;
    };
    p.filteredShadows = scene.hasTransparency() && p.shadowMaps.any();
    p.bandLayers = (g.grid.bands() + 3) / 4;
    const std::vector<float> depthChannel = packDepthChannels(p, scene, g, frame);

    std::vector<double> emissionOverLambda, attenuation;
    for (size_t mi = 0; mi < g.materials.size(); ++mi) {
        const MaterialOnGrid& m = g.materials[mi];
        bool specular = std::any_of(m.specular.begin(), m.specular.end(), [](double v) { return v != 0.0; });
        const float lobeTableBase = lobeTable(m, specular);
        // A medium's attenuation per unit of the frame, for exp2: a·log2(10)·unit (m⁻¹ × m); a
        // slab's across its thickness, a·log2(10)·d.
        attenuation.clear();
        for (double a : m.absorbance) attenuation.push_back(a * std::log2(10.0) * frame.unit_m());
        for (double a : m.slabAbsorbance) attenuation.push_back(a * std::log2(10.0) * m.slabThickness);
        // View-independent fluorescence coupling per light, (Φ/π)·Σ a·E_l·λ·Δλ, summed in double
        // so the shader only multiplies by the light's geometric factor.
        std::vector<float> coupling(MAX_LIGHTS, 0.0f);
        float excitationBase = -1.0f;
        emissionOverLambda.assign(m.diffuse.size(), 0.0);
        if (m.fluorescent && !p.fluorescenceSpectra) {
            // ê/λ scaled by 2^−shift, the coupling by 2^shift (scaledEmissionOverLambda).
            ScaledEmission scaled = scaledEmissionOverLambda(m, g);
            emissionOverLambda = std::move(scaled.overLambda);
            const int shift = scaled.shift;
            for (size_t i = 0; i < order.size(); ++i) {
                const auto& E = g.lights[order[i]];
                double sum = 0.0;
                for (size_t b = 0; b < E.size(); ++b) sum += m.excitation[b] * E[b] * g.wavelengths_nm[b];
                coupling[i] = float(std::ldexp(m.quantum_yield / M_PI * sum * g.grid.step_nm, shift));
            }
            // Under a coloured shadow the coupling is Σ of these terms × τ, taken per fragment.
            if (p.filteredShadows) {
                excitationBase = float(p.shadowExcitation.size());
                for (size_t i = 0; i < order.size(); ++i) {
                    const auto& E = g.lights[order[i]];
                    for (int j = 0; j < p.bandLayers; ++j) {
                        glm::vec4 v(0.0f);
                        for (int c = 0; c < 4; ++c) {
                            const size_t b = size_t(4 * j + c);
                            if (b < E.size())
                                v[c] = float(std::ldexp(m.quantum_yield / M_PI * m.excitation[b] * E[b] *
                                                            g.wavelengths_nm[b] * g.grid.step_nm,
                                                        shift));
                        }
                        p.shadowExcitation.push_back(v);
                    }
                }
            }
        }
        for (int pass = 0; pass < passes; ++pass) {
            gpu::GpuMaterialBlock& b = p.materials[size_t(pass) * g.materials.size() + mi];
            scatterBands(m.diffuse, pass, b.diffuse);
            scatterBands(m.specular, pass, b.specular);
            scatterBands(emissionOverLambda, pass, b.emissionOverLambda);
            b.params = glm::vec4(float(m.gloss), float(pass * MAX_OUTPUTS), excitationBase, depthChannel[mi]);
            b.lobe = glm::vec4(lobeTableBase, glm::vec2(lobeWarp(m.gloss)), 0.0f);
            b.switches = glm::uvec4(materialSwitches(m, specular), 0u, 0u, 0u);
            for (int l = 0; l < MAX_LIGHTS; ++l) b.coupling[l / 4][l % 4] = coupling[l];
            scatterBands(m.transmittance, pass, b.transmittance);
            scatterBands(attenuation, pass, b.attenuation);
            scatterBands(m.ior, pass, b.ior);
            scatterBands(m.emitted, pass, b.emitted);
            // Past the grid's last band a slab is air (n = 1: nothing reflected, all transmitted),
            // so that the padding lanes stay finite for the tonemap pass, which reads whole layers.
            if (m.isSlab())
                for (int k = 0; k < MAX_OUTPUTS; ++k)
                    for (int c = 0; c < 4; ++c)
                        if (size_t(pass) * BANDS_PER_PASS + size_t(4 * k + c) >= m.ior.size()) b.ior[k][c] = 1.0f;
        }
    }
    // With a Donaldson matrix in the scene every fluorescent material re-emits from per-light
    // spectra; under a coloured shadow they are a matrix–vector product with τ per fragment:
    // F_l(λo) = Σᵢ τ(λᵢ)·[(1/π)·D(λᵢ, λo)·E_l(λᵢ)·Δλ], the bracket stored per (material, light) as
    // rows of input bands, each BAND_LAYERS vec4 of output bands (the rank-one form expanded to
    // its matrix Φ·a(λᵢ)·ê(λo)·λᵢ/λo).
    if (p.filteredShadows && p.fluorescenceSpectra) {
        const size_t n = g.wavelengths_nm.size(), layers = size_t(p.bandLayers);
        const double step = g.grid.step_nm;
        for (size_t mi = 0; mi < g.materials.size(); ++mi) {
            const MaterialOnGrid& m = g.materials[mi];
            if (!m.fluorescent) continue;
            const float base = float(p.shadowExcitation.size());
            for (int pass = 0; pass < passes; ++pass) p.materials[size_t(pass) * g.materials.size() + mi].params.z = base;
            auto matrix = [&](size_t in, size_t o) {
                return m.isMatrix() ? m.donaldson[in * n + o]
                                    : m.quantum_yield * m.excitation[in] * m.emission[o] * g.wavelengths_nm[in] /
                                          g.wavelengths_nm[o];
            };
            for (size_t i = 0; i < order.size(); ++i) {
                const std::vector<double>& E = g.lights[order[i]];
                for (size_t in = 0; in < 4 * layers; ++in)
                    for (size_t k = 0; k < layers; ++k) {
                        glm::vec4 v(0.0f);
                        for (int c = 0; c < 4; ++c) {
                            const size_t o = 4 * k + size_t(c);
                            if (in < n && o < n) v[c] = float(matrix(in, o) * E[in] * step / M_PI);
                        }
                        p.shadowExcitation.push_back(v);
                    }
            }
        }
    }
    if (p.shadowExcitation.empty()) p.shadowExcitation.push_back(glm::vec4(0.0f));
    packFluorescence(p, scene, g, order, passes);
    return p;
}

std::vector<double> crossingDepthBounds(const PackedScene& p, const SceneOnGrid& g) {
    const size_t channels = size_t(std::max(0, p.depthChannels));
    std::vector<double> sheets(channels, 0.0);
    std::vector<glm::dvec3> lower(channels, glm::dvec3(std::numeric_limits<double>::infinity()));
    std::vector<glm::dvec3> upper(channels, glm::dvec3(-std::numeric_limits<double>::infinity()));
    std::vector<bool> medium(channels, false), drawn(channels, false);
    for (const PackedDraw& d : p.draws) {
        const MaterialOnGrid& m = g.materials[d.material];
        if (!m.isFilter() && !m.isMedium()) continue;
        const int e = int(p.materials[d.material].params.w);
        if (e < 0 || size_t(e) >= channels) continue;
        drawn[size_t(e)] = true;
        medium[size_t(e)] = m.isMedium();
        sheets[size_t(e)] += double(d.indexCount / 3);
        lower[size_t(e)] = glm::min(lower[size_t(e)], glm::dvec3(d.lower));
        upper[size_t(e)] = glm::max(upper[size_t(e)], glm::dvec3(d.upper));
    }
    std::vector<double> most(channels, 0.0);
    for (size_t e = 0; e < channels; ++e)
        if (drawn[e]) most[e] = 2.0 * (medium[e] ? glm::length(upper[e] - lower[e]) : sheets[e]);
    return most;
}

PackedScene packResponses(const Scene& scene, const SceneOnGrid& g, const std::vector<std::vector<double>>& weights,
                          const LocalFrame& frame, uint64_t texelLimit) {
    const size_t channels = weights.size(), n = g.wavelengths_nm.size();
    if (channels == 0 || channels > 4 * RESPONSE_VEC4)
        failRuntime("the response pass carries 1 to {} detector channels, not {}", 4 * RESPONSE_VEC4, channels);
    for (const auto& w : weights)
        if (w.size() != n) failRuntime("detector weights on {} bands for a scene on {}", w.size(), n);
    // Geometry, light vectors and the materials' parameters as for the band passes (one pass); the
    // spectra those blocks hold are not read.
    PackedScene p = pack(scene, g, 1, frame);
    p.responses = true;
    p.fluorescenceSpectra = false;
    p.responseChannels = int(channels);
    // Outside the detector's support every per-band record is exactly zero (w_cb = 0): the shader's
    // band loops run over [first, end) only.
    p.responseFirstLayer = std::numeric_limits<int>::max();
    for (const auto& w : weights)
        for (size_t b = 0; b < n; ++b)
            if (w[b] != 0.0) {
                p.responseFirstLayer = std::min(p.responseFirstLayer, int(b / 4));
                p.responseEndLayer = std::max(p.responseEndLayer, int(b / 4) + 1);
            }
    if (p.responseEndLayer == 0) p.responseFirstLayer = 0;
    PackedScene counted;
    const std::vector<size_t> order = lightOrder(scene, counted);
    const size_t lights = order.size();
    // The detector's response to a spectrum s: Σ_b w_cb·s_b, into RESPONSE_VEC4 vec4 at dst.
    auto respond = [&](const std::vector<double>& s, glm::vec4* dst) {
        for (size_t c = 0; c < channels; ++c) {
            double r = 0.0;
            for (size_t b = 0; b < n; ++b) r += weights[c][b] * s[b];
            if (!(std::fabs(r) <= double(std::numeric_limits<float>::max())))
                failRuntime("a detector response of {:g} is beyond the largest float32", r);
            dst[c / 4][int(c % 4)] = float(r);
        }
    };
    std::vector<double> product(n);
    p.responseBlocks.assign(g.materials.size(), gpu::GpuResponseBlock{});
    for (gpu::GpuResponseBlock& block : p.responseBlocks) block.spectra = block.tables = glm::ivec4(-1);
    // Seen through sheets and media, the sums' terms stay per band (GpuResponseBlock::spectra): after
    // the optical-depth channels' rows, per opaque material, light, term and channel, BAND_LAYERS vec4.
    if (scene.hasTransparency()) {
        // The detector-weighted spectrum w_cb·s_b, 4·⌈channels/4⌉ channels × BAND_LAYERS vec4 (zero
        // past the channels and the bands), appended to the texel buffer's rows.
        const size_t padded = 4 * ((channels + 3) / 4), layers = size_t(p.bandLayers);
        // w_cb·s_b rounded to float, as the records hold it and the tables take it.
        std::vector<std::vector<double>> weighted(padded, std::vector<double>(n, 0.0));
        auto weigh = [&](const std::vector<double>& s) -> const std::vector<std::vector<double>>& {
            for (size_t c = 0; c < channels; ++c)
                for (size_t b = 0; b < n; ++b) weighted[c][b] = double(float(weights[c][b] * s[b]));
            return weighted;
        };
        auto appendWeighted = [&](const std::vector<double>& s) {
            const std::vector<std::vector<double>>& w = weigh(s);
            for (size_t c = 0; c < padded; ++c)
                for (size_t j = 0; j < layers; ++j) {
                    glm::vec4 v(0.0f);
                    for (size_t k = 0; k < 4 && 4 * j + k < n; ++k) v[int(k)] = float(w[c][4 * j + k]);
                    p.depthSpectra.push_back(v);
                }
        };
        // An opaque material's terms in the records' (and tables') order: per light, ρ_d·E then ρ_s·E.
        auto forEachTerm = [&](const MaterialOnGrid& m, const auto& use) {
            for (size_t i = 0; i < lights; ++i) {
                const std::vector<double>& E = g.lights[order[i]];
                for (const std::vector<double>* rho : {&m.diffuse, &m.specular}) {
                    for (size_t b = 0; b < n; ++b) product[b] = (*rho)[b] * E[b];
                    use(product);
                }
            }
        };
        // A rank-one fluorescent material's emission ê(λ)/λ as pack() scales it, rounded to float as
        // the band passes read it (their product, bit for bit).
        auto emissionOf = [&](const MaterialOnGrid& m) {
            std::vector<double> emission = scaledEmissionOverLambda(m, g).overLambda;
            for (double& v : emission) v = double(float(v));
            return emission;
        };
        for (size_t mi = 0; mi < g.materials.size(); ++mi) {
            const MaterialOnGrid& m = g.materials[mi];
            if (m.isTransparent()) continue;
            p.responseBlocks[mi].spectra.x = int(p.depthSpectra.size());
            forEachTerm(m, appendWeighted);
        }
        for (size_t mi = 0; mi < g.materials.size(); ++mi) {
            const MaterialOnGrid& m = g.materials[mi];
            if (!m.fluorescent || m.isTransparent()) continue;
            p.responseBlocks[mi].spectra.z = int(p.depthSpectra.size());
            appendWeighted(emissionOf(m));
        }
        // A slab reflects the environment: the detector-weighted light spectra w_cb·E_lb, and its
        // normal (Scene::transparencyInResponses: one planar slab, every normal parallel).
        for (const PackedDraw& d : p.draws) {
            if (!g.materials[d.material].isSlab()) continue;
            const float* nv = p.vertices[size_t(int64_t(p.indices[d.firstIndex]) + d.vertexOffset)].normal;
            const glm::vec3 normal = glm::normalize(glm::vec3(nv[0], nv[1], nv[2]));
            const int rows = int(p.depthSpectra.size());
            for (size_t i = 0; i < lights; ++i) appendWeighted(g.lights[order[i]]);
            for (gpu::GpuResponseBlock& block : p.responseBlocks) {
                block.spectra.y = rows;
                block.slabNormal = glm::vec4(normal, 0.0f);
            }
            break;
        }
        // A rank-one fluorescent material's emission summed over the bands (seen through nothing).
        for (size_t mi = 0; mi < g.materials.size(); ++mi) {
            if (p.responseBlocks[mi].spectra.z < 0) continue;
            p.responseBlocks[mi].tables.z = int(p.depthSpectra.size());
            for (size_t c = 0; c < padded; c += 4) {
                glm::vec4 total(0.0f);
                for (size_t k = 0; k < 4; ++k)
                    if (c + k < channels) {
                        double sum = 0.0;
                        const glm::vec4* rows = &p.depthSpectra[size_t(p.responseBlocks[mi].spectra.z) + (c + k) * layers];
                        for (size_t j = 0; j < layers; ++j) sum += double(rows[j].x) + rows[j].y + rows[j].z + rows[j].w;
                        total[int(k)] = float(sum);
                    }
                p.depthSpectra.push_back(total);
            }
        }
        // Single-crossing tables (render/crossing_tables.h): per opaque material, light and term, and
        // per fluorescent material's emission, F and h·F' on every sheet's and medium's axis.
        const CrossingAxes axes = crossingAxes(crossingDepthBounds(p, g), p.depthSpectra, p.bandLayers, n,
                                               p.responseFirstLayer, p.responseEndLayer);
        uint64_t tables = 0;
        for (size_t mi = 0; mi < g.materials.size(); ++mi)
            tables += (p.responseBlocks[mi].spectra.x >= 0 ? 2 * lights : 0) + (p.responseBlocks[mi].spectra.z >= 0 ? 1 : 0);
        const uint64_t tableRows = tables * uint64_t(axes.totalNodes) * 2 * (padded / 4) + axes.channels.size();
        // At most kCrossingTableTexels (32 MiB; filters.json's: 2 MiB, 670 nodes on 5 channels): a
        // scene of many materials and lights beside deep filters would spend seconds of loading on
        // them, so it sums per band.
        constexpr uint64_t kCrossingTableTexels = uint64_t(1) << 21;
        if (axes.totalNodes > 0 && tableRows <= kCrossingTableTexels && p.depthSpectra.size() + tableRows <= texelLimit) {
            p.crossingHeader = int(p.depthSpectra.size());
            p.crossingNodes = axes.totalNodes;
            for (const CrossingAxis& a : axes.channels)
                p.depthSpectra.push_back(a.nodes > 0 ? glm::vec4(float(1.0 / a.h), float(a.nodes - 1), float(a.first),
                                                                 float(double(a.nodes - 1) * a.h))
                                                     : glm::vec4(0.0f, 0.0f, 0.0f, -1.0f));
            for (size_t mi = 0; mi < g.materials.size(); ++mi) {
                if (p.responseBlocks[mi].spectra.x < 0) continue;
                p.responseBlocks[mi].tables.x = int(p.depthSpectra.size());
                forEachTerm(g.materials[mi], [&](const std::vector<double>& s) { appendCrossingTable(p.depthSpectra, axes, weigh(s)); });
            }
            for (size_t mi = 0; mi < g.materials.size(); ++mi) {
                if (p.responseBlocks[mi].spectra.z < 0) continue;
                p.responseBlocks[mi].tables.y = int(p.depthSpectra.size());
                appendCrossingTable(p.depthSpectra, axes, weigh(emissionOf(g.materials[mi])));
            }
            p.crossingTexels = p.depthSpectra.size() - size_t(p.crossingHeader);
        }
    }
    p.responseTextureSlots.assign(g.materials.size(), {-1, -1, -1});
    for (size_t mi = 0; mi < g.materials.size(); ++mi) {
        const MaterialOnGrid& m = g.materials[mi];
        gpu::GpuResponseBlock& block = p.responseBlocks[mi];
        for (size_t i = 0; i < lights; ++i) {
            const std::vector<double>& E = g.lights[order[i]];
            for (size_t b = 0; b < n; ++b) product[b] = m.diffuse[b] * E[b];
            respond(product, &block.diffuse[i * RESPONSE_VEC4]);
            for (size_t b = 0; b < n; ++b) product[b] = m.specular[b] * E[b];
            respond(product, &block.specular[i * RESPONSE_VEC4]);
            if (m.fluorescent) respond(fluorescentRadiance(m, E, g), &block.fluorescence[i * RESPONSE_VEC4]);
        }
        // A reflectance texture T scales the material's spectrum texel by texel: its response
        // texture holds Σ_b w_cb·ρ_b·T_b·E_lb for every light (bilinear filtering is linear, so
        // filtering responses is the response of the filtered spectra).
        auto responseTexture = [&](int texture, const std::vector<double>& rho) {
            const TextureOnGrid& t = g.textures[size_t(texture)];
            TextureOnGrid r;
            r.width = t.width;
            r.height = t.height;
            r.channels = int(std::max<size_t>(1, lights)) * 4 * RESPONSE_VEC4;
            r.data.assign(size_t(t.width) * t.height * size_t(r.channels), 0.0f);
            std::vector<double> u(channels * n);  // w_cb·ρ_b·E_lb for one light
            for (size_t i = 0; i < lights; ++i) {
                const std::vector<double>& E = g.lights[order[i]];
                for (size_t c = 0; c < channels; ++c)
                    for (size_t b = 0; b < n; ++b) u[c * n + b] = weights[c][b] * rho[b] * E[b];
                for (size_t px = 0; px < size_t(t.width) * t.height; ++px) {
                    const float* texel = t.texel(int(px % size_t(t.width)), int(px / size_t(t.width)));
                    float* out = &r.data[px * size_t(r.channels) + i * 4 * RESPONSE_VEC4];
                    for (size_t c = 0; c < channels; ++c) {
                        double sum = 0.0;
                        const double* uc = &u[c * n];
                        for (size_t b = 0; b < n; ++b) sum += uc[b] * texel[b];
                        out[c] = float(sum);
                    }
                }
            }
            p.responseTextures.push_back(std::move(r));
            return int(p.responseTextures.size()) - 1;
        };
        if (m.diffuseTexture >= 0) p.responseTextureSlots[mi][0] = responseTexture(m.diffuseTexture, m.diffuse);
        if (m.specularTexture >= 0) p.responseTextureSlots[mi][1] = responseTexture(m.specularTexture, m.specular);
        if (m.normalTexture >= 0) {
            p.responseTextures.push_back(g.textures[size_t(m.normalTexture)]);
            p.responseTextureSlots[mi][2] = int(p.responseTextures.size()) - 1;
        }
    }
    return p;
}

}  // namespace metamer
