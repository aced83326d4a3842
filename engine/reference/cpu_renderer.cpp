#include "reference/cpu_renderer.h"

#include "core/cpu_count.h"
#include "core/parallel_for.h"

#include "reference/hemisphere_lobe.h"
#include "spectral/dielectric.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <numeric>
#include <numbers>
#include <thread>

namespace metamer {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRayTMin = 1e-9;  // frame units (about the scene's size) along a unit direction

// The SceneOnGrid must come from this scene: a mismatch is a programming error, not input.
void checkOnGrid(const Scene& scene, const SceneOnGrid& g) {
    const size_t n = static_cast<size_t>(g.grid.bands());
    auto sized = [n](const std::vector<double>& v) { return v.size() == n; };
    if (g.wavelengths_nm.size() != n || g.lights.size() != scene.lights.size() ||
        g.materials.size() != scene.materials.size())
        failRuntime("reference renderer: the resampled spectra do not match the scene "
                    "({} lights, {} materials vs {} and {})",
                    g.lights.size(), g.materials.size(), scene.lights.size(), scene.materials.size());
    for (const auto& e : g.lights)
        if (!sized(e)) failRuntime("reference renderer: a light spectrum has the wrong band count");
    for (const auto& m : g.materials) {
        auto texture = [&](int i, bool normals) {
            if (i < 0) return;
            if (size_t(i) >= g.textures.size() || g.textures[size_t(i)].normals != normals ||
                g.textures[size_t(i)].channels != (normals ? 3 : int(n)))
                failRuntime("reference renderer: a material's texture {} does not match the resampled textures", i);
        };
        texture(m.diffuseTexture, false);
        texture(m.specularTexture, false);
        texture(m.normalTexture, true);
        const bool fluorescenceSized =
            !m.fluorescent || (m.isMatrix() ? m.donaldson.size() == n * n : sized(m.excitation) && sized(m.emission));
        if (!sized(m.diffuse) || !sized(m.specular) || !fluorescenceSized)
            failRuntime("reference renderer: a material spectrum has the wrong band count");
    }
}

// Bilinear filtering of a texture at texture coordinates uv (docs/physics.md, "Textures"): texel
// centres at (i + ½)/W, coordinates repeating; `out` gets the texture's channels.
// The triangles of the opaque meshes, or of the transparent ones.
std::vector<BvhTriangle> trianglesOf(const Scene& scene, const LocalFrame& frame, bool transparent) {
    return Bvh::collectTriangles(scene, frame, [&](const Mesh& mesh) {
        return scene.materials[mesh.material].isTransparent() == transparent;
    });
}

}  // namespace

ReferenceRenderer::ReferenceRenderer(const Scene& scene, const SceneOnGrid& onGrid,
                                     const ReferenceOptions& options)
    : scene_(scene),
      onGrid_(onGrid),
      options_(options),
      bands_(onGrid.grid.bands()),
      frame_((checkMeshes(scene), localFrameFor(scene, scene.camera))),
      camera_(frame_.camera(scene.camera)),
      bvh_(trianglesOf(scene, frame_, false)),
      clearBvh_(trianglesOf(scene, frame_, true)) {
    if (options_.ssaa < 1 || options_.ssaa > 64)
        failInput(Where{"", "ssaa", 0}, "supersampling {} is outside 1..64", options_.ssaa);
    if (options_.threads < 0)
        failInput(Where{"", "threads", 0}, "thread count {} is negative", options_.threads);
    checkOnGrid(scene, onGrid);

    const Camera& cam = camera_;
    Where camWhere{scene.file.string(), "camera", 0};
    if (cam.width < 1 || cam.height < 1)
        failInput(camWhere, "image size {}×{} must be at least 1×1", cam.width, cam.height);
    const glm::dvec3 toTarget = cam.target - cam.position;
    if (!(glm::length(toTarget) > 0.0)) failInput(camWhere, "camera target equals its position");
    f_ = glm::normalize(toTarget);
    const glm::dvec3 side = glm::cross(f_, cam.up);
    if (!(glm::length(side) > 1e-12 * glm::length(cam.up)))
        failInput(camWhere, "camera up is parallel to the view direction");
    r_ = glm::normalize(side);
    u_ = glm::cross(r_, f_);
    aspect_ = static_cast<double>(cam.width) / cam.height;
    if (cam.projection == Camera::Projection::Perspective) {
        if (!(cam.fov_y_deg > 0.0 && cam.fov_y_deg < 180.0))
            failInput(camWhere, "field of view {}° is outside (0, 180)", cam.fov_y_deg);
        tanHalf_ = std::tan(0.5 * cam.fov_y_deg * kPi / 180.0);
    } else {
        if (!(cam.height_m > 0.0)) failInput(camWhere, "orthographic height {} m must be > 0", cam.height_m);
        halfHeight_ = 0.5 * cam.height_m;
    }

    // Shadowing lights get a bit of `blocked`; shadow rays start past a distance relative to the
    // scene's size (see inShadow).
    shadowBit_.assign(scene.lights.size(), -1);
    for (size_t l = 0, k = 0; l < scene.lights.size(); ++l)
        if (scene.lights[l].castsShadows()) shadowBit_[l] = int(k++ % 64);
    pairedHemisphere_ = pairedWithPreviousHemisphere(scene.lights);
    for (const Light& light : scene.lights) lightPositions_.push_back(frame_.position(light.position));
    const bool hemisphereLights = std::any_of(scene.lights.begin(), scene.lights.end(),
                                              [](const Light& l) { return l.type == Light::Type::Hemisphere; });
    for (const Bvh* b : {&bvh_, &clearBvh_})
        for (const BvhTriangle& t : b->triangles())
            for (const glm::dvec3& p : {t.p0, t.p1, t.p2})
                sceneScale_ = std::max({sceneScale_, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});

    // View-independent spectral factors, per (material, light). A hemisphere light's spectrum is
    // its radiance L; its geometric factors (below) make the diffuse term ρd·L·(1 + n·u)/2.
    const size_t nm = scene.materials.size(), nl = scene.lights.size();
    diffuseTerm_.assign(nm * nl * bands_, 0.0);
    specularTerm_.assign(nm * nl * bands_, 0.0);
    fluorescenceTerm_.assign(nm * nl * bands_, 0.0);
    hasSpecular_.assign(nm, false);
    hasFluorescence_.assign(nm, false);
    const double step = onGrid.grid.step_nm;
    for (size_t m = 0; m < nm; ++m) {
        const MaterialOnGrid& mat = onGrid.materials[m];
        hasSpecular_[m] = std::any_of(mat.specular.begin(), mat.specular.end(),
                                      [](double v) { return v != 0.0; });
        hasFluorescence_[m] = mat.fluorescent;
        // The hemisphere lights' lobe table of this gloss (shared with the GPU path, built once).
        lobeTables_.push_back(hemisphereLights && hasSpecular_[m] && mat.gloss > 0.0 ? lobeTableFor(mat.gloss) : nullptr);
        const double lobeNorm = (mat.gloss + 8.0) / (8.0 * kPi);
        for (size_t l = 0; l < nl; ++l) {
            const std::vector<double>& e = onGrid.lights[l];
            const size_t o = termOffset(static_cast<uint32_t>(m), l);
            for (int b = 0; b < bands_; ++b) {
                diffuseTerm_[o + b] = mat.diffuse[b] * e[b] / kPi;
                specularTerm_[o + b] = mat.specular[b] * e[b] * lobeNorm;
            }
            if (!mat.fluorescent) continue;
            if (mat.isMatrix()) {
                // The Donaldson matrix (nm⁻¹) re-radiates E(λi)·Δλ from each band into every band:
                // L_f(λo) = (1/π)·Σᵢ D(λi, λo)·E(λi)·Δλ.
                for (int out = 0; out < bands_; ++out) {
                    double sum = 0.0;
                    for (int in = 0; in < bands_; ++in) sum += mat.donaldson[size_t(in) * bands_ + out] * e[in];
                    fluorescenceTerm_[o + out] = sum * step / kPi;
                }
                continue;
            }
            // Absorbed photons ∝ S = Σ a·E·λ·Δλ (the Riemann sum over the render grid); a fraction
            // Φ is re-emitted with shape ê, each photon at λ carrying energy ∝ 1/λ.
            double s = 0.0;
            for (int b = 0; b < bands_; ++b)
                s += mat.excitation[b] * e[b] * onGrid.wavelengths_nm[b] * step;
            for (int b = 0; b < bands_; ++b)
                fluorescenceTerm_[o + b] =
                    mat.quantum_yield / kPi * mat.emission[b] / onGrid.wavelengths_nm[b] * s;
        }
    }
    // Interreflection, the reference's own way (reference/indirect_light.h): patches half the
    // scene's element size (or its opaque objects' diagonal / 48), 32 × 32 strata.
    if (scene.interreflection && options_.interreflection) {
        glm::dvec3 lo(INFINITY), hi(-INFINITY);
        for (const BvhTriangle& t : bvh_.triangles())
            for (const glm::dvec3& p : {t.p0, t.p1, t.p2}) {
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
        const double diagonal = bvh_.triangles().empty() ? 1.0 : std::max(1e-12, glm::length(hi - lo));
        const double patch = scene.interreflection->elementSize_m ? frame_.length(*scene.interreflection->elementSize_m) / 2.0
                                                                  : diagonal / 48.0;
        indirect_ = std::make_unique<IndirectLight>(
            scene, onGrid, bvh_,
            [this](uint32_t t, const glm::dvec3& p, const glm::dvec3& n, const glm::dvec2& uv, double* out) {
                directRadiosity(t, p, n, uv, out);
            },
            patch, 32);
    }
}

void ReferenceRenderer::directRadiosity(uint32_t triangle, const glm::dvec3& p, const glm::dvec3& n, const glm::dvec2& uv,
                                        double* out) const {
    const uint32_t material = scene_.meshes[bvh_.triangles()[triangle].mesh].material;
    const MaterialOnGrid& mat = onGrid_.materials[material];
    std::vector<double> texel(static_cast<size_t>(bands_), 1.0);
    if (mat.diffuseTexture >= 0) onGrid_.textures[size_t(mat.diffuseTexture)].bilinear(uv, texel.data());
    std::fill(out, out + bands_, 0.0);
    for (size_t l = 0; l < scene_.lights.size(); ++l) {
        const Light& light = scene_.lights[l];
        double g = 0.0;  // as shade()'s gDiffuse
        if (light.type == Light::Type::Ambient) {
            g = 1.0;
        } else if (light.type == Light::Type::Hemisphere) {
            g = kPi * (1.0 + glm::dot(n, light.up)) / 2.0;
        } else {
            glm::dvec3 w;
            double falloff = 1.0;
            if (light.type == Light::Type::Directional) {
                w = -glm::normalize(light.direction);
            } else {
                const glm::dvec3 toLight = lightPositions_[l] - p;
                const double d2 = glm::dot(toLight, toLight);
                if (!(d2 > 0.0)) continue;
                w = toLight / std::sqrt(d2);
                falloff = frame_.inverseSquareUnit() / d2;
            }
            const double cosI = glm::dot(n, w);
            if (cosI <= 0.0) continue;
            if (shadowBit_[l] >= 0 && inShadow(l, p, w, triangle)) continue;
            g = cosI * falloff;
        }
        const size_t o = termOffset(material, l);
        for (int b = 0; b < bands_; ++b) out[b] += kPi * g * (diffuseTerm_[o + b] * texel[size_t(b)] + fluorescenceTerm_[o + b]);
    }
}

void ReferenceRenderer::addIndirect(uint32_t material, uint32_t triangle, const glm::dvec3& p, const glm::dvec3& n,
                                    const double* diffuseTexture, double* radiance) const {
    const MaterialOnGrid& mat = onGrid_.materials[material];
    std::vector<double> H(static_cast<size_t>(bands_));
    indirect_->irradiance(p, n, triangle, H.data());
    if (options_.quantity == SurfaceQuantity::Illumination) {  // H/π, what a white diffuser would send
        for (int b = 0; b < bands_; ++b) radiance[b] += H[size_t(b)] / kPi;
        return;
    }
    for (int b = 0; b < bands_; ++b)
        radiance[b] += mat.diffuse[size_t(b)] * (diffuseTexture ? diffuseTexture[b] : 1.0) * H[size_t(b)] / kPi;
    if (!mat.fluorescent) return;
    // What H excites, as the direct light's terms: a Donaldson matrix's (1/π)·Σᵢ D(λi, λ)·H(λi)·Δλ,
    // a pair's (Φ/π)·ê(λ)/λ·Σ a·H·λ·Δλ.
    const double step = onGrid_.grid.step_nm;
    if (mat.isMatrix()) {
        for (int out = 0; out < bands_; ++out) {
            double sum = 0.0;
            for (int in = 0; in < bands_; ++in) sum += mat.donaldson[size_t(in) * size_t(bands_) + size_t(out)] * H[size_t(in)];
            radiance[out] += sum * step / kPi;
        }
        return;
    }
    double absorbed = 0.0;
    for (int b = 0; b < bands_; ++b) absorbed += mat.excitation[size_t(b)] * H[size_t(b)] * onGrid_.wavelengths_nm[size_t(b)] * step;
    for (int b = 0; b < bands_; ++b)
        radiance[b] += mat.quantum_yield / kPi * mat.emission[size_t(b)] / onGrid_.wavelengths_nm[size_t(b)] * absorbed;
}

Ray ReferenceRenderer::cameraRay(double px, double py) const {
    const Camera& cam = camera_;
    const double ndcX = 2.0 * px / cam.width - 1.0;
    const double ndcY = 1.0 - 2.0 * py / cam.height;
    Ray ray;
    if (cam.projection == Camera::Projection::Perspective) {
        ray.origin = cam.position;
        ray.direction =
            glm::normalize(f_ + ndcX * tanHalf_ * aspect_ * r_ + ndcY * tanHalf_ * u_);
    } else {
        ray.origin = cam.position + ndcX * halfHeight_ * aspect_ * r_ + ndcY * halfHeight_ * u_;
        ray.direction = f_;
    }
    return ray;
}

int32_t ReferenceRenderer::trace(const Ray& ray, double* radiance, uint64_t* blocked, uint32_t* crossings) const {
    std::fill(radiance, radiance + bands_, 0.0);
    if (blocked) *blocked = 0;
    if (crossings) *crossings = 0;
    auto hit = bvh_.intersect(ray, kRayTMin);
    // The ground-truth maps are of the opaque surface seen, not of what lies in front of it.
    const bool seenThrough = options_.quantity == SurfaceQuantity::Radiance && !clearBvh_.triangles().empty();
    if (!hit) {
        // The background is black, but a slab in front of it still reflects.
        if (seenThrough) {
            const uint32_t c = transmit(ray, std::numeric_limits<double>::infinity(), radiance);
            if (crossings) *crossings = c;
        }
        return kBackgroundId;
    }
    uint64_t b = 0;
    uint32_t lit = 0;  // the shadow rays' crossings
    shade(*hit, ray, radiance, b, lit);
    if (!clearBvh_.triangles().empty()) {
        uint32_t c = (seenThrough ? transmit(ray, hit->t, radiance) : 0) + lit;
        if (c == kMixedCrossings) --c;
        if (crossings) *crossings = c;
    }
    if (blocked) *blocked = b;
    return static_cast<int32_t>(bvh_.triangles()[hit->index].mesh);
}

// Straight through (docs/physics.md, "Transparent objects"): every crossing of a sheet multiplies
// by T(λ); every medium multiplies by 10^(−a(λ)·ℓ), ℓ the length of the ray inside its mesh before
// tEnd — entered where the ray meets a face from outside (against its outward normal), left where
// it meets one from inside; a ray that leaves first started inside (the camera is in the medium).
// Each mesh counts on its own, so overlapping media multiply. A ray through an edge meets both
// triangles at the same t: hits of one mesh, on the same side, within 1e-9 of the scene's size
// count once, as a rasterizer covers a pixel by one of the two.
uint32_t ReferenceRenderer::crossings(const Ray& ray, double tMin, double tEnd, std::vector<double>& factor,
                                      double* reflected) const {
    factor.clear();
    // Every crossing along the whole ray: a medium whose first crossing is a way out holds the
    // ray's start, even where the opaque surface comes before that crossing.
    std::vector<RayHit> all = clearBvh_.allHits(ray, tMin, std::numeric_limits<double>::infinity());
    if (all.empty()) return 0;
    const auto& tris = clearBvh_.triangles();
    auto faceNormal = [&](const RayHit& h) {
        const BvhTriangle& t = tris[h.index];
        return glm::cross(t.p1 - t.p0, t.p2 - t.p0);
    };
    auto entering = [&](const RayHit& h) { return glm::dot(faceNormal(h), ray.direction) < 0.0; };
    std::sort(all.begin(), all.end(), [](const RayHit& a, const RayHit& b) { return a.t < b.t; });
    // One crossing per surface: a ray through a shared edge meets both triangles at the same t.
    const double same = 1e-9 * std::max(sceneScale_, std::isfinite(tEnd) ? tEnd : 0.0);
    std::vector<RayHit> hits;
    for (size_t i = 0; i < all.size(); ++i) {
        const uint32_t mesh = tris[all[i].index].mesh;
        const bool in = entering(all[i]);
        bool repeated = false;
        for (size_t j = i; j-- > 0 && all[i].t - all[j].t <= same;)
            repeated = repeated || (tris[all[j].index].mesh == mesh && entering(all[j]) == in);
        if (!repeated) hits.push_back(all[i]);
    }
    struct Inside {
        uint32_t mesh;
        int depth;            // how many of its faces the ray is behind (nested shells of one mesh)
        double since, length;  // where the ray last went in; the path inside so far
    };
    // Every medium on the ray, inside from the start when its first crossing leads out.
    std::vector<Inside> media;
    for (const RayHit& h : hits) {
        const uint32_t mesh = tris[h.index].mesh;
        if (!onGrid_.materials[scene_.meshes[mesh].material].isMedium()) continue;
        if (std::none_of(media.begin(), media.end(), [&](const Inside& m) { return m.mesh == mesh; }))
            media.push_back(Inside{mesh, entering(h) ? 0 : 1, 0.0, 0.0});
    }
    // The media's transmittance from the start to t; with t infinite, over their completed paths.
    auto mediaFactor = [&](int b, double t) {
        double depth = 0.0;
        for (const Inside& m : media) {
            const double length = m.length + (m.depth > 0 && std::isfinite(t) ? t - m.since : 0.0);
            depth += onGrid_.materials[scene_.meshes[m.mesh].material].absorbance[size_t(b)] * length * frame_.unit_m();
        }
        return std::pow(10.0, -depth);
    };
    uint32_t signature = 0;  // a sum over the crossings before tEnd: the same set, the same value
    factor.assign(size_t(bands_), 1.0);  // the sheets' and slabs' product so far
    for (const RayHit& h : hits) {
        if (h.t >= tEnd) break;
        const uint32_t mesh = tris[h.index].mesh;
        const bool in = entering(h);
        signature += (mesh + 1) * 2654435761u + (in ? 1u : 2u);
        const MaterialOnGrid& mat = onGrid_.materials[scene_.meshes[mesh].material];
        if (mat.isFilter()) {
            for (int b = 0; b < bands_; ++b) factor[size_t(b)] *= mat.transmittance[size_t(b)];
        } else if (mat.isSlab()) {
            // Fresnel at both faces, the glass's absorption along the refracted path, the
            // reflections inside added incoherently (spectral/dielectric.h): T and R per band at
            // this crossing's angle; what the slab reflects is its mirror direction's light.
            const glm::dvec3 n = glm::normalize(faceNormal(h));
            const double cosI = std::min(1.0, std::fabs(glm::dot(n, ray.direction)));
            const glm::dvec3 mirror = ray.direction - 2.0 * glm::dot(ray.direction, n) * n;
            for (int b = 0; b < bands_; ++b) {
                const double ior = mat.ior[size_t(b)];
                const double tau = slabInternalTransmittance(ior, cosI, mat.slabAbsorbance[size_t(b)], mat.slabThickness);
                const SlabReflectanceTransmittance rt = slab(ior, cosI, tau);
                if (reflected)
                    reflected[b] += factor[size_t(b)] * mediaFactor(b, h.t) * rt.reflectance * environment(mirror, b);
                factor[size_t(b)] *= rt.transmittance;
            }
        } else {
            auto it = std::find_if(media.begin(), media.end(), [&](const Inside& m) { return m.mesh == mesh; });
            if (in) {
                if (it->depth++ == 0) it->since = h.t;
            } else if (it->depth > 0 && --it->depth == 0) {
                it->length += h.t - it->since;
            }
        }
    }
    // The ray ends inside a medium (an opaque surface in it, a light in it). A ray to a
    // directional light cannot, unless rounding lost its way out through an edge: nothing then.
    for (int b = 0; b < bands_; ++b) factor[size_t(b)] *= mediaFactor(b, tEnd);
    return signature == kMixedCrossings ? signature - 1 : signature;
}

// The light a mirror sees in direction r: the hemisphere lights' radiance L where r·up > 0, and an
// ambient light's E/π (uniform radiance that gives irradiance E). Points and directional lights
// are single directions: a mirror shows them as points, not drawn (docs/physics.md, "Transparent objects").
double ReferenceRenderer::environment(const glm::dvec3& r, int b) const {
    double l = 0.0;
    for (size_t i = 0; i < scene_.lights.size(); ++i) {
        const Light& light = scene_.lights[i];
        if (light.type == Light::Type::Ambient) l += onGrid_.lights[i][size_t(b)] / kPi;
        if (light.type == Light::Type::Hemisphere && glm::dot(r, light.up) > 0.0) l += onGrid_.lights[i][size_t(b)];
    }
    return l;
}

uint32_t ReferenceRenderer::transmit(const Ray& ray, double tEnd, double* radiance) const {
    thread_local std::vector<double> factor, reflected;
    reflected.assign(size_t(bands_), 0.0);
    const uint32_t signature = crossings(ray, kRayTMin, tEnd, factor, reflected.data());
    for (size_t b = 0; b < factor.size(); ++b) radiance[b] = radiance[b] * factor[b] + reflected[b];
    return signature;
}

// Coloured shadows: what reaches p from light l through the transparent objects on the way, the
// shadow ray's crossings as the primary ray's (same start past the surface as inShadow).
bool ReferenceRenderer::lightTransmittance(size_t l, const glm::dvec3& p, const glm::dvec3& w,
                                           std::vector<double>& factor, uint32_t& signature) const {
    const Light& light = scene_.lights[l];
    const double eps = 1e-9 * sceneScale_;
    double tEnd = std::numeric_limits<double>::infinity();
    if (light.type == Light::Type::Point) tEnd = glm::length(lightPositions_[l] - p);
    signature = crossings(Ray{p, w}, eps, tEnd, factor);
    return !factor.empty();
}

// Fluorescence per unit geometric factor under light l filtered by `tau`: the excitation sums of
// the constructor's terms taken over E·τ instead of E.
void ReferenceRenderer::filteredFluorescence(uint32_t material, size_t l, const double* tau, double* out) const {
    const MaterialOnGrid& mat = onGrid_.materials[material];
    const std::vector<double>& e = onGrid_.lights[l];
    const double step = onGrid_.grid.step_nm;
    if (mat.isMatrix()) {
        for (int o = 0; o < bands_; ++o) {
            double sum = 0.0;
            for (int i = 0; i < bands_; ++i) sum += mat.donaldson[size_t(i) * bands_ + o] * e[i] * tau[i];
            out[o] = sum * step / kPi;
        }
        return;
    }
    double s = 0.0;
    for (int b = 0; b < bands_; ++b) s += mat.excitation[b] * e[b] * tau[b] * onGrid_.wavelengths_nm[b] * step;
    for (int b = 0; b < bands_; ++b) out[b] = mat.quantum_yield / kPi * mat.emission[b] / onGrid_.wavelengths_nm[b] * s;
}

// A shadow ray from the hit point towards the light: any triangle but the one it leaves, past
// 1e-9 of the scene's size (rounding of p, which lies on its triangle only to ~1e-16 of it), and,
// for a point light, short of the light by as much. Exact: no bias, no shadow map.
bool ReferenceRenderer::inShadow(size_t l, const glm::dvec3& p, const glm::dvec3& w, uint32_t triangle) const {
    const Light& light = scene_.lights[l];
    const double eps = 1e-9 * sceneScale_;
    double tMax = std::numeric_limits<double>::infinity();
    if (light.type == Light::Type::Point) tMax = glm::length(lightPositions_[l] - p) - eps;
    return tMax > eps && bvh_.occluded(Ray{p, w}, eps, tMax, triangle);
}

ReferenceRenderer::SurfacePoint ReferenceRenderer::surfacePoint(const RayHit& hit, const Ray& ray) const {
    const BvhTriangle& tri = bvh_.triangles()[hit.index];
    const Mesh& mesh = scene_.meshes[tri.mesh];
    SurfacePoint s;
    s.mesh = tri.mesh;
    s.material = mesh.material;
    const double b1 = hit.b1, b2 = hit.b2, b0 = 1.0 - b1 - b2;

    // The point on the triangle (as a rasterizer interpolates it), and its normals.
    s.p = b0 * tri.p0 + b1 * tri.p1 + b2 * tri.p2;
    s.ng = glm::normalize(glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0));
    glm::dvec3 n = s.ng;
    bool mappable = true;  // normal maps apply unless usable vertex normals cancel here
    if (!mesh.normals.empty()) {
        const uint32_t* idx = &mesh.indices[3 * static_cast<size_t>(tri.triangle)];
        const glm::dvec3 sum =
            b0 * mesh.normals[idx[0]] + b1 * mesh.normals[idx[1]] + b2 * mesh.normals[idx[2]];
        // Opposing vertex normals can cancel; the face normal is then the only sensible choice.
        if (glm::length(sum) > 1e-12) {
            n = glm::normalize(sum);
        } else {
            bool anyUsable = false;
            for (int k = 0; k < 3; ++k) anyUsable = anyUsable || glm::length(mesh.normals[idx[k]]) > 1e-12;
            mappable = !anyUsable;
        }
    }
    const MaterialOnGrid& mat = onGrid_.materials[s.material];
    const uint32_t* corner = &mesh.indices[3 * static_cast<size_t>(tri.triangle)];
    if (!mesh.uvs.empty()) s.uv = b0 * mesh.uvs[corner[0]] + b1 * mesh.uvs[corner[1]] + b2 * mesh.uvs[corner[2]];
    // Normal mapping, on the front side's normal: the map's vector m in the frame (t, b, n), t the
    // interpolated tangent made perpendicular to n, b = cross(n, t)·w.
    if (mat.normalTexture >= 0 && !mesh.tangents.empty() && mappable) {
        const glm::dvec4 t4 = b0 * mesh.tangents[corner[0]] + b1 * mesh.tangents[corner[1]] + b2 * mesh.tangents[corner[2]];
        glm::dvec3 t = glm::dvec3(t4) - n * glm::dot(n, glm::dvec3(t4));
        double m[3];
        onGrid_.textures[size_t(mat.normalTexture)].bilinear(s.uv, m);
        glm::dvec3 mv(m[0], m[1], m[2]);
        if (glm::dot(t, t) > 1e-12 && glm::dot(mv, mv) > 1e-12) {
            t = glm::normalize(t);
            const glm::dvec3 b = glm::cross(n, t) * (t4.w < 0.0 ? -1.0 : 1.0);
            mv = glm::normalize(mv);
            n = glm::normalize(t * mv.x + b * mv.y + n * mv.z);
        }
    }
    // Two-sided: a back face is shaded as if seen from its front.
    if (glm::dot(s.ng, -ray.direction) < 0.0) n = -n;
    s.n = n;
    return s;
}

void ReferenceRenderer::shade(const RayHit& hit, const Ray& ray, double* radiance, uint64_t& blocked,
                              uint32_t& crossed, double* specular) const {
    const SurfacePoint surface = surfacePoint(hit, ray);
    const Mesh& mesh = scene_.meshes[surface.mesh];
    const uint32_t material = surface.material;
    const MaterialOnGrid& mat = onGrid_.materials[material];
    const glm::dvec3& p = surface.p;
    const glm::dvec3& ng = surface.ng;
    const glm::dvec3& n = surface.n;
    const glm::dvec2& uv = surface.uv;
    const glm::dvec3 v = -ray.direction;

    // Textured reflectance: the texture's bands multiply the material's (precomputed) terms.
    thread_local std::vector<double> diffuseTex, specularTex;
    const bool diffuseTextured = mat.diffuseTexture >= 0, specularTextured = mat.specularTexture >= 0;
    if (diffuseTextured) {
        diffuseTex.resize(bands_);
        onGrid_.textures[size_t(mat.diffuseTexture)].bilinear(uv, diffuseTex.data());
    }
    if (specularTextured) {
        specularTex.resize(bands_);
        onGrid_.textures[size_t(mat.specularTexture)].bilinear(uv, specularTex.data());
    }
    // The mask's specular test (`specular` given) asks about the radiance, whatever the maps are.
    const SurfaceQuantity quantity = specular ? SurfaceQuantity::Radiance : options_.quantity;
    if (quantity == SurfaceQuantity::Reflectance) {  // ρd, as the diffuse term has it
        for (int b = 0; b < bands_; ++b) radiance[b] = mat.diffuse[size_t(b)] * (diffuseTextured ? diffuseTex[b] : 1.0);
        return;
    }
    const bool illumination = quantity == SurfaceQuantity::Illumination;

    const double gloss = onGrid_.materials[material].gloss;
    glm::dvec2 previousLobe(0.0);  // the last hemisphere light's (I, I_unoccluded): a ground after its sky shares it
    thread_local std::vector<double> lightFilter, filteredEmission;
    for (size_t l = 0; l < scene_.lights.size(); ++l) {
        const Light& light = scene_.lights[l];
        double gDiffuse = 0.0, gSpecular = 0.0;  // geometric factors; fluorescence uses gDiffuse
        const double* tau = nullptr;             // the light's transmittance to p per band, when filtered
        if (light.type == Light::Type::Ambient) {
            gDiffuse = 1.0;  // irradiance E on every surface, whatever its orientation
        } else if (light.type == Light::Type::Hemisphere) {
            // Uniform radiance L from every ω with ω·u > 0: irradiance π·L·(1 + n·u)/2, exactly;
            // the lobe's integral over the lune n·ω > 0, u·ω > 0 from the lobe table (hemisphere_lobe.h).
            gDiffuse = kPi * (1.0 + glm::dot(n, light.up)) / 2.0;
            if (hasSpecular_[material]) {
                const glm::dvec2 lobe = pairedHemisphere_[l]
                                            ? glm::dvec2(std::max(0.0, previousLobe.y - previousLobe.x), previousLobe.y)
                                            : hemisphereLobe(lobeTables_[material].get(), n, v, light.up);
                gSpecular = lobe.x;
                previousLobe = lobe;
            }
        } else {
            glm::dvec3 w;        // unit vector towards the light
            double falloff = 1.0;  // 1/d² for a point light, m⁻²
            if (light.type == Light::Type::Directional) {
                w = -glm::normalize(light.direction);
            } else {
                const glm::dvec3 toLight = lightPositions_[l] - p;  // in the frame's units
                const double d2 = glm::dot(toLight, toLight);
                if (!(d2 > 0.0)) continue;  // a point light on the surface: no defined direction
                w = toLight / std::sqrt(d2);
                falloff = frame_.inverseSquareUnit() / d2;
            }
            const double cosI = glm::dot(n, w);
            if (cosI <= 0.0) continue;  // lit from behind the shading normal: nothing
            if (shadowBit_[l] >= 0 && inShadow(l, p, w, hit.index)) {
                blocked |= uint64_t(1) << shadowBit_[l];
                continue;  // blocked: no reflection, no fluorescence
            }
            // Not blocked, but perhaps filtered: a coloured shadow (what casts shadows filters).
            uint32_t through = 0;
            if (shadowBit_[l] >= 0 && !clearBvh_.triangles().empty() && lightTransmittance(l, p, w, lightFilter, through)) {
                tau = lightFilter.data();
                crossed += through * uint32_t(2 * l + 3);
            }
            gDiffuse = cosI * falloff;
            if (hasSpecular_[material]) {
                const glm::dvec3 hv = w + v;
                const double len = glm::length(hv);
                const double nh = len > 0.0 ? std::max(0.0, glm::dot(n, hv / len)) : 0.0;
                const double lobe = gloss == 0.0 ? 1.0 : std::pow(nh, gloss);  // x^0 = 1
                gSpecular = gDiffuse * lobe;
            }
        }
        const size_t o = termOffset(material, l);
        const double* d = &diffuseTerm_[o];
        auto filtered = [tau](int b) { return tau ? tau[b] : 1.0; };
        if (illumination) {  // E/π with the diffuse term's geometric factor, shadow and filter; ρd := 1
            const std::vector<double>& e = onGrid_.lights[l];
            for (int b = 0; b < bands_; ++b) radiance[b] += gDiffuse * e[size_t(b)] / kPi * filtered(b);
            continue;
        }
        if (diffuseTextured)
            for (int b = 0; b < bands_; ++b) radiance[b] += gDiffuse * d[b] * diffuseTex[b] * filtered(b);
        else
            for (int b = 0; b < bands_; ++b) radiance[b] += gDiffuse * d[b] * filtered(b);
        if (gSpecular != 0.0) {
            const double* s = &specularTerm_[o];
            if (specularTextured)
                for (int b = 0; b < bands_; ++b) radiance[b] += gSpecular * s[b] * specularTex[b] * filtered(b);
            else
                for (int b = 0; b < bands_; ++b) radiance[b] += gSpecular * s[b] * filtered(b);
            if (specular) {  // the lobe's share, for the ground truth's specular flag (reference/geometry_maps.h)
                for (int b = 0; b < bands_; ++b)
                    specular[b] += gSpecular * s[b] * (specularTextured ? specularTex[b] : 1.0) * filtered(b);
            }
        }
        if (hasFluorescence_[material]) {
            // Excited by the light that arrives: through a filter, the sums over E·τ.
            const double* f = &fluorescenceTerm_[o];
            if (tau) {
                filteredEmission.resize(size_t(bands_));
                filteredFluorescence(material, l, tau, filteredEmission.data());
                f = filteredEmission.data();
            }
            for (int b = 0; b < bands_; ++b) radiance[b] += gDiffuse * f[b];
        }
    }
    // A self-luminous surface's own radiance, seen on its front (the side its winding faces).
    if (!illumination && mat.isEmitter() && glm::dot(ng, v) > 0.0)
        for (int b = 0; b < bands_; ++b) radiance[b] += mat.emitted[size_t(b)];
    // The light that bounced, on the side the eye sees (n faces it); a closed mesh's inside gets none.
    if (indirect_ && !specular && (glm::dot(ng, v) >= 0.0 || !mesh.closed))
        addIndirect(material, hit.index, p, n, diffuseTextured ? diffuseTex.data() : nullptr, radiance);
}

int32_t ReferenceRenderer::pixel(int x, int y, double* radiance, uint64_t* blocked, uint32_t* crossings) const {
    const int s = options_.ssaa;
    std::vector<double> sample(bands_);
    std::fill(radiance, radiance + bands_, 0.0);
    int32_t id = kBackgroundId;
    uint64_t shadows = 0;
    uint32_t crossed = 0;
    for (int j = 0; j < s; ++j) {
        for (int i = 0; i < s; ++i) {
            const Ray ray = cameraRay(x + (i + 0.5) / s, y + (j + 0.5) / s);
            uint64_t b = 0;
            uint32_t c = 0;
            const int32_t sid = trace(ray, sample.data(), &b, &c);
            if (i == 0 && j == 0) {
                id = sid;
                shadows = b;
                crossed = c;
            } else {
                if (sid != id) id = kMixedId;
                if (b != shadows) shadows = kMixedShadows;
                if (c != crossed) crossed = kMixedCrossings;
            }
            for (int b = 0; b < bands_; ++b) radiance[b] += sample[b];
        }
    }
    const double inv = 1.0 / (static_cast<double>(s) * s);
    for (int b = 0; b < bands_; ++b) radiance[b] *= inv;
    if (blocked) *blocked = shadows;
    if (crossings) *crossings = crossed;
    return id;
}

ReferenceImage ReferenceRenderer::render() const {
    const int w = scene_.camera.width, h = scene_.camera.height;
    ReferenceImage image;
    image.cube = SpectralCube(w, h, onGrid_.grid);
    image.objectId.assign(static_cast<size_t>(w) * h, kBackgroundId);
    image.shadows.assign(static_cast<size_t>(w) * h, 0);
    image.crossings.assign(static_cast<size_t>(w) * h, 0);

    int threads = options_.threads;
    if (threads == 0) threads = usableCpuCount();
    threads = std::min(threads, h);

    // Rows are handed out one at a time; each pixel depends only on its own rays, so the result
    // is the same for any thread count.
    std::atomic<int> nextRow{0}, rowsDone{0};
    std::exception_ptr failure;
    std::mutex failureMutex;
    // The calling thread also renders rows, and reports progress between its own rows (a throw
    // from the report stops every thread as a failure does).
    auto lastReport = std::chrono::steady_clock::now();
    auto work = [&](bool caller) {
        try {
            std::vector<double> radiance(bands_);
            for (int y = nextRow++; y < h; y = nextRow++) {
                for (int x = 0; x < w; ++x) {
                    const size_t at = static_cast<size_t>(y) * w + x;
                    image.objectId[at] = pixel(x, y, radiance.data(), &image.shadows[at], &image.crossings[at]);
                    float* out = image.cube.pixel(x, y);
                    for (int b = 0; b < bands_; ++b) out[b] = static_cast<float>(radiance[b]);
                }
                ++rowsDone;
                if (caller && options_.progress &&
                    std::chrono::steady_clock::now() - lastReport > std::chrono::milliseconds(250)) {
                    lastReport = std::chrono::steady_clock::now();
                    options_.progress(rowsDone.load(), h);
                }
            }
        } catch (...) {
            std::lock_guard<std::mutex> lock(failureMutex);
            if (!failure) failure = std::current_exception();
            nextRow = h;  // let the other threads stop early
        }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(work, false);
    work(true);
    for (auto& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
    return image;
}

ReferenceImage renderReference(const Scene& scene, const SceneOnGrid& onGrid,
                               const ReferenceOptions& options) {
    return ReferenceRenderer(scene, onGrid, options).render();
}

// --- The ground truth's geometry maps (reference/geometry_maps.h) ---------------------------------

bool ReferenceRenderer::specularDominates(const RayHit& hit, const Ray& ray) const {
    thread_local std::vector<double> total, specular;
    total.assign(size_t(bands_), 0.0);
    specular.assign(size_t(bands_), 0.0);
    uint64_t blocked = 0;
    uint32_t crossed = 0;
    shade(hit, ray, total.data(), blocked, crossed, specular.data());
    const double all = std::accumulate(total.begin(), total.end(), 0.0);
    const double lobe = std::accumulate(specular.begin(), specular.end(), 0.0);
    return all > 0.0 && lobe > kSpecularShare * all;
}

GeometryMaps ReferenceRenderer::geometryMaps() const {
    const int W = camera_.width, H = camera_.height, s = options_.ssaa;
    const size_t pixels = size_t(W) * size_t(H);
    GeometryMaps g;
    g.width = W;
    g.height = H;
    g.object.assign(pixels, kBackgroundId);
    g.material.assign(pixels, kBackgroundId);
    g.depth_m.assign(pixels, 0.0f);
    g.normal.assign(3 * pixels, 0.0f);
    g.mask.assign(pixels, 0);
    const bool clear = !clearBvh_.triangles().empty();
    const double centre = (s / 2 + 0.5) / s;
    auto meshAt = [&](const Ray& ray) {
        const auto hit = bvh_.intersect(ray, kRayTMin);
        return hit ? int32_t(bvh_.triangles()[hit->index].mesh) : kBackgroundId;
    };
    parallelFor(pixels, options_.threads, 256, [&](size_t at) {
        const int x = int(at % size_t(W)), y = int(at / size_t(W));
        const Ray ray = cameraRay(x + centre, y + centre);
        const auto hit = bvh_.intersect(ray, kRayTMin);
        uint8_t mask = 0;
        if (clear && !clearBvh_.allHits(ray, kRayTMin, hit ? hit->t : std::numeric_limits<double>::infinity()).empty())
            mask |= kTruthTransparent;
        if (!hit) {
            mask |= kTruthBackground;
        } else {
            const SurfacePoint sp = surfacePoint(*hit, ray);
            const MaterialOnGrid& mat = onGrid_.materials[sp.material];
            g.object[at] = int32_t(sp.mesh);
            g.material[at] = int32_t(sp.material);
            g.depth_m[at] = float(hit->t * frame_.unit_m());
            const glm::dvec3 n(glm::dot(sp.n, r_), glm::dot(sp.n, u_), -glm::dot(sp.n, f_));
            for (int c = 0; c < 3; ++c) g.normal[3 * at + size_t(c)] = float(n[c]);
            if (mat.fluorescent) mask |= kTruthFluorescent;
            if (mat.isEmitter() && glm::dot(sp.ng, -ray.direction) > 0.0) mask |= kTruthEmitter;
            if (hasSpecular_[sp.material] && specularDominates(*hit, ray)) mask |= kTruthSpecular;
        }
        // Sub-samples on another surface: the maps average more than one.
        for (int j = 0; j < s && s > 1 && !(mask & kTruthEdge); ++j)
            for (int i = 0; i < s; ++i)
                if (meshAt(cameraRay(x + (i + 0.5) / s, y + (j + 0.5) / s)) != g.object[at]) {
                    mask |= kTruthEdge;
                    break;
                }
        g.mask[at] = mask;
    });
    // A neighbour that sees another surface, or through other transparent objects: the rasterizer
    // may take the other at this pixel.
    std::vector<uint8_t> edge(pixels, 0);
    parallelFor(pixels, options_.threads, 4096, [&](size_t at) {
        const int x = int(at % size_t(W)), y = int(at / size_t(W));
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int nx = x + dx, ny = y + dy;
                if (nx < 0 || ny < 0 || nx >= W || ny >= H) continue;
                const size_t there = size_t(ny) * size_t(W) + size_t(nx);
                if (g.object[there] != g.object[at] ||
                    ((g.mask[there] ^ g.mask[at]) & kTruthTransparent) != 0)
                    edge[at] = kTruthEdge;
            }
    });
    for (size_t at = 0; at < pixels; ++at) g.mask[at] |= edge[at];
    return g;
}

}  // namespace metamer
