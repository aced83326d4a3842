#include "reference/indirect_light.h"

#include "core/cpu_count.h"
#include "core/error.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <thread>
#include <tuple>

namespace metamer {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kSamples = 6;  // a patch's direct light, and a bright patch's area factor: over its cut into 6 × 6
constexpr size_t kBright = 512;  // at most this many bright patches

// Two unit vectors completing n to an orthonormal basis (Duff et al. 2017).
void basis(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z), c = n.x * n.y * a;
    t = glm::dvec3(1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x);
    b = glm::dvec3(c, sign + n.y * n.y * a, -n.y);
}

// Direction (u, v) of the S × S cosine-weighted strata around n (Malley: uniform on the disk,
// lifted to the hemisphere), each carrying 1/S² of the irradiance of a uniform radiance.
glm::dvec3 stratum(const glm::dvec3& n, const glm::dvec3& t, const glm::dvec3& b, int u, int v, int strata) {
    const double s = (u + 0.5) / strata, phi = 2.0 * kPi * (v + 0.5) / strata, r = std::sqrt(s);
    return r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0, 1.0 - s)) * n;
}

// Patch (up/down, i, j) of a triangle cut k × k, in a compact order: the k(k+1)/2 upright ones row
// by row, then the k(k−1)/2 upside-down ones.
uint32_t patchIndex(uint32_t k, uint32_t i, uint32_t j, bool down) {
    if (!down) return i * k - i * (i - 1) / 2 + j;
    return k * (k + 1) / 2 + i * (k - 1) - i * (i - 1) / 2 + j;
}

}  // namespace

IndirectLight::IndirectLight(const Scene& scene, const SceneOnGrid& g, const Bvh& opaque, const DirectRadiosity& direct,
                             double patchSize, int strata)
    : scene_(scene), g_(g), bvh_(opaque), bands_(g.grid.bands()), strata_(strata) {
    if (!(patchSize > 0.0) || strata < 1) failRuntime("IndirectLight: patch size {} and strata {}", patchSize, strata);
    const auto& tris = bvh_.triangles();
    firstPatch_.resize(tris.size());
    cuts_.resize(tris.size());
    twoSided_.resize(tris.size());
    std::vector<double> reflectance;  // per patch × band
    std::vector<double> emission;     // per patch × band
    std::vector<char> emitting;       // per patch: a self-luminous front
    std::vector<double> texel(static_cast<size_t>(bands_)), e(static_cast<size_t>(bands_)), sample(static_cast<size_t>(bands_));
    for (uint32_t t = 0; t < tris.size(); ++t) {
        const BvhTriangle& tri = tris[t];
        const Mesh& mesh = scene.meshes[tri.mesh];
        const MaterialOnGrid& mat = g.materials[mesh.material];
        const double longest = std::max({glm::length(tri.p1 - tri.p0), glm::length(tri.p2 - tri.p1), glm::length(tri.p0 - tri.p2)});
        const uint32_t k = std::max<uint32_t>(1, uint32_t(std::ceil(longest / patchSize)));
        cuts_[t] = k;
        twoSided_[t] = !mesh.closed;
        firstPatch_[t] = uint32_t(centroid_.size());
        const glm::dvec3 face = glm::normalize(glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0));
        const uint32_t* idx = &mesh.indices[size_t(tri.triangle) * 3];
        const bool hasNormals = mesh.normals.size() == mesh.positions.size(), hasUvs = !mesh.uvs.empty();
        std::vector<glm::dvec3> sideCentroid(k * k);
        std::vector<glm::dvec3> shading(k * k);
        std::vector<glm::dvec2> uv(k * k);
        std::vector<std::array<glm::dvec3, 3>> patchCorners(k * k);
        for (uint32_t i = 0; i < k; ++i)
            for (uint32_t j = 0; i + j < k; ++j)
                for (int down = 0; down < 2; ++down) {
                    if (down && i + j + 2 > k) continue;
                    const double b1 = (i + (down ? 2.0 : 1.0) / 3.0) / k, b2 = (j + (down ? 2.0 : 1.0) / 3.0) / k;
                    const double b0 = 1.0 - b1 - b2;
                    const uint32_t p = patchIndex(k, i, j, down != 0);
                    sideCentroid[p] = b0 * tri.p0 + b1 * tri.p1 + b2 * tri.p2;
                    // The patch's corners (barycentric (i, j) grid points), for its direct light.
                    auto at = [&](double u, double v) { return (1.0 - u - v) * tri.p0 + u * tri.p1 + v * tri.p2; };
                    patchCorners[p] = down ? std::array<glm::dvec3, 3>{at((i + 1.0) / k, double(j) / k), at((i + 1.0) / k, (j + 1.0) / k),
                                                                         at(double(i) / k, (j + 1.0) / k)}
                                           : std::array<glm::dvec3, 3>{at(double(i) / k, double(j) / k), at((i + 1.0) / k, double(j) / k),
                                                                         at(double(i) / k, (j + 1.0) / k)};
                    glm::dvec3 n = face;
                    if (hasNormals) {
                        const glm::dvec3 v = b0 * mesh.normals[idx[0]] + b1 * mesh.normals[idx[1]] + b2 * mesh.normals[idx[2]];
                        if (glm::length(v) > 1e-12) n = glm::normalize(v);
                    }
                    shading[p] = glm::dot(n, face) < 0.0 ? -n : n;
                    uv[p] = hasUvs ? b0 * mesh.uvs[idx[0]] + b1 * mesh.uvs[idx[1]] + b2 * mesh.uvs[idx[2]] : glm::dvec2(0.0);
                }
        for (int side = 0; side < (twoSided_[t] ? 2 : 1); ++side)
            for (uint32_t p = 0; p < k * k; ++p) {
                const double flip = side == 0 ? 1.0 : -1.0;
                centroid_.push_back(sideCentroid[p]);
                normal_.push_back(flip * face);
                corners_.push_back(patchCorners[p]);
                area_.push_back(0.5 * glm::length(glm::cross(patchCorners[p][1] - patchCorners[p][0],
                                                            patchCorners[p][2] - patchCorners[p][0])));
                triangle_.push_back(t);
                if (mat.diffuseTexture >= 0) g.textures[size_t(mat.diffuseTexture)].bilinear(uv[p], texel.data());
                // Within [0, 1], as the GPU path's solve takes it (docs/physics.md, "Interreflection").
                for (int b = 0; b < bands_; ++b)
                    reflectance.push_back(std::clamp(mat.diffuse[size_t(b)] * (mat.diffuseTexture >= 0 ? texel[size_t(b)] : 1.0), 0.0, 1.0));
                // The direct light averaged over the patch: the centroids of its cut into
                // kSamples² equal parts (a point light near a surface peaks sharply).
                std::fill(e.begin(), e.end(), 0.0);
                const auto& c = patchCorners[p];
                for (int a = 0; a < kSamples; ++a)
                    for (int d = 0; a + d < kSamples; ++d)
                        for (int upside = 0; upside < 2; ++upside) {
                            if (upside && a + d + 2 > kSamples) continue;
                            const double u = (a + (upside ? 2.0 : 1.0) / 3.0) / kSamples, v = (d + (upside ? 2.0 : 1.0) / 3.0) / kSamples;
                            direct(t, (1.0 - u - v) * c[0] + u * c[1] + v * c[2], flip * shading[p], uv[p], sample.data());
                            for (int b = 0; b < bands_; ++b) e[size_t(b)] += sample[size_t(b)] / (kSamples * kSamples);
                        }
                // A self-luminous surface's front sends π·L_e besides (a Lambertian emitter's exitance).
                if (mat.isEmitter() && side == 0)
                    for (int b = 0; b < bands_; ++b) e[size_t(b)] += kPi * mat.emitted[size_t(b)];
                emitting.push_back(mat.isEmitter() && side == 0);
                emission.insert(emission.end(), e.begin(), e.end());
            }
    }
    const size_t n = centroid_.size();
    // The brightest patches — where a light near a surface makes a hot spot, too small for the
    // strata to find evenly — are gathered from by integrating over their area instead.
    {
        // Bright: sending at least 8 times the area-weighted mean (a uniformly lit room has none),
        // and first every self-luminous patch where they cover less than half the surfaces (an
        // emitting wall lights the floor at its foot; a room of glowing walls is what the strata,
        // whose rows sum to exactly 1, gather best).
        std::vector<std::tuple<bool, double, uint32_t>> power;
        std::vector<double> top(n, 0.0);
        double sent = 0.0, area = 0.0, glowing = 0.0;
        for (size_t j = 0; j < n; ++j) glowing += emitting[j] ? area_[j] : 0.0;
        if (!(glowing < 0.5 * std::accumulate(area_.begin(), area_.end(), 0.0))) emitting.assign(n, 0);
        for (size_t j = 0; j < n; ++j) {
            for (int b = 0; b < bands_; ++b) top[j] = std::max(top[j], emission[j * size_t(bands_) + size_t(b)]);
            sent += top[j] * area_[j];
            area += area_[j];
            power.push_back({emitting[j] != 0, top[j] * area_[j], uint32_t(j)});
        }
        const double mean = area > 0.0 ? sent / area : 0.0;
        std::sort(power.begin(), power.end(), std::greater<>());
        bright_.assign(n, false);
        for (size_t k = 0; k < power.size() && brightList_.size() < kBright; ++k)
            if (const uint32_t j = std::get<2>(power[k]); emitting[j] || top[j] > 8.0 * mean) {
                bright_[j] = true;
                brightList_.push_back(j);
            }
    }

    // Each patch's row: the share of its strata that first hit each patch (but a bright one), and
    // the bright patches' factors by area.
    std::vector<std::vector<std::pair<uint32_t, double>>> rows(n);
    std::atomic<size_t> next{0};
    auto cast = [&] {
        for (size_t i; (i = next.fetch_add(1)) < n;) {
            glm::dvec3 t, b;
            basis(normal_[i], t, b);
            std::map<uint32_t, int> hits;
            for (int u = 0; u < strata_; ++u)
                for (int v = 0; v < strata_; ++v) {
                    const long j = patchHit(Ray{centroid_[i], stratum(normal_[i], t, b, u, v, strata_)}, triangle_[i]);
                    if (j >= 0 && !bright_[size_t(j)]) ++hits[uint32_t(j)];
                }
            for (const auto& [j, count] : hits) rows[i].push_back({j, double(count) / (double(strata_) * strata_)});
            for (uint32_t j : brightList_)
                if (j != i)
                    if (const double f = areaFactor(centroid_[i], normal_[i], triangle_[i], j); f > 0.0) rows[i].push_back({j, f});
        }
    };
    std::vector<std::thread> pool;
    for (int k = 1; k < usableCpuCount(); ++k) pool.emplace_back(cast);
    cast();
    for (std::thread& th : pool) th.join();

    // Band by band in order of wavelength, Gauss–Seidel sweeps until nothing changes by more than
    // 10⁻¹⁰ of the largest radiosity; fluorescence re-emits the irradiance of the other bands (their
    // latest), so the whole is repeated until a round changes nothing either.
    radiosity_ = emission;
    std::vector<double> H(n * size_t(bands_), 0.0);
    const double step = g.grid.step_nm;
    auto material = [&](size_t i) -> const MaterialOnGrid& { return g.materials[scene.meshes[bvh_.triangles()[triangle_[i]].mesh].material]; };
    // The radiosity band `out` of patch i gets from its irradiance in band `in` by fluorescence.
    auto reemitted = [&](const MaterialOnGrid& m, int out, int in) {
        if (!m.fluorescent) return 0.0;
        if (m.isMatrix()) return m.donaldson[size_t(in) * size_t(bands_) + size_t(out)] * step;
        return m.quantum_yield * m.emission[size_t(out)] / g.wavelengths_nm[size_t(out)] * m.excitation[size_t(in)] *
               g.wavelengths_nm[size_t(in)] * step;
    };
    const bool fluorescence = std::any_of(g.materials.begin(), g.materials.end(), [](const MaterialOnGrid& m) { return m.fluorescent; });
    for (int round = 0; round < (fluorescence ? 50 : 1); ++round) {
        double roundChange = 0.0, largest = 0.0;
        for (int b = 0; b < bands_; ++b) {
            for (int sweep = 0; sweep < 100000; ++sweep) {
                double change = 0.0, top = 0.0;
                for (size_t i = 0; i < n; ++i) {
                    double h = 0.0;
                    for (const auto& [j, f] : rows[i]) h += f * radiosity_[size_t(j) * size_t(bands_) + size_t(b)];
                    H[i * size_t(bands_) + size_t(b)] = h;
                    double value = emission[i * size_t(bands_) + size_t(b)] + reflectance[i * size_t(bands_) + size_t(b)] * h;
                    const MaterialOnGrid& m = material(i);
                    if (m.fluorescent)
                        for (int in = 0; in < bands_; ++in) value += reemitted(m, b, in) * (in == b ? h : H[i * size_t(bands_) + size_t(in)]);
                    double& old = radiosity_[i * size_t(bands_) + size_t(b)];
                    change = std::max(change, std::fabs(value - old));
                    top = std::max(top, std::fabs(value));
                    old = value;
                }
                ++sweeps_;
                roundChange = std::max(roundChange, change);
                largest = std::max(largest, top);
                if (change <= 1e-10 * top) break;
            }
        }
        if (round > 0 && roundChange <= 1e-10 * largest) break;
    }
}

long IndirectLight::patchHit(const Ray& ray, uint32_t skip) const {
    const std::optional<RayHit> hit = bvh_.intersect(ray, 1e-9);
    if (!hit || hit->index == skip) return -1;
    const BvhTriangle& tri = bvh_.triangles()[hit->index];
    const glm::dvec3 face = glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0);
    const bool front = glm::dot(ray.direction, face) < 0.0;
    if (!front && !twoSided_[hit->index]) return -1;  // a closed mesh's inside: not interreflected
    const uint32_t k = cuts_[hit->index];
    const double u = std::clamp(hit->b1, 0.0, 1.0) * k, v = std::clamp(hit->b2, 0.0, 1.0) * k;
    uint32_t i = std::min(uint32_t(u), k - 1), j = std::min(uint32_t(v), k - 1);
    if (i + j > k - 1) {  // rounding past the hypotenuse: the last upright patch of the row
        j = k - 1 - i;
    }
    const bool down = (u - i) + (v - j) > 1.0 && i + j + 2 <= k;
    const uint32_t local = patchIndex(k, i, j, down);
    return long(firstPatch_[hit->index] + (front ? 0 : k * k) + local);
}

double IndirectLight::areaFactor(const glm::dvec3& x, const glm::dvec3& n, uint32_t skip, uint32_t j) const {
    // The point-to-area kernel cos θx·cos θj/(π r²) over the patch cut into kSamples² equal parts,
    // each seen or not along a ray.
    // As many parts a side as the patch is large against its distance (up to kSamples).
    const auto& c = corners_[j];
    const double size = std::max({glm::length(c[1] - c[0]), glm::length(c[2] - c[1]), glm::length(c[0] - c[2])});
    const int m = std::clamp(int(std::ceil(4.0 * size / std::max(1e-300, glm::length(centroid_[j] - x)))), 1, kSamples);
    const double dA = area_[j] / (m * m);
    double sum = 0.0;
    for (int a = 0; a < m; ++a)
        for (int d = 0; a + d < m; ++d)
            for (int upside = 0; upside < 2; ++upside) {
                if (upside && a + d + 2 > m) continue;
                const double u = (a + (upside ? 2.0 : 1.0) / 3.0) / m, v = (d + (upside ? 2.0 : 1.0) / 3.0) / m;
                const glm::dvec3 y = (1.0 - u - v) * c[0] + u * c[1] + v * c[2];
                const glm::dvec3 dir = y - x;
                const double r2 = glm::dot(dir, dir), r = std::sqrt(r2);
                if (!(r > 0.0)) continue;
                const double cx = glm::dot(n, dir) / r, cj = -glm::dot(normal_[j], dir) / r;
                if (cx <= 0.0 || cj <= 0.0) continue;
                if (bvh_.occluded(Ray{x, dir / r}, 1e-9, r * (1.0 - 1e-9), skip)) continue;
                sum += cx * cj * dA / (kPi * r2);
            }
    return sum;
}

void IndirectLight::irradiance(const glm::dvec3& p, const glm::dvec3& n, uint32_t skip, double* H) const {
    std::fill(H, H + bands_, 0.0);
    glm::dvec3 t, b;
    basis(n, t, b);
    const double weight = 1.0 / (double(strata_) * strata_);
    for (int u = 0; u < strata_; ++u)
        for (int v = 0; v < strata_; ++v) {
            const long j = patchHit(Ray{p, stratum(n, t, b, u, v, strata_)}, skip);
            if (j < 0 || bright_[size_t(j)]) continue;
            const double* B = &radiosity_[size_t(j) * size_t(bands_)];
            for (int band = 0; band < bands_; ++band) H[band] += weight * B[band];
        }
    for (uint32_t j : brightList_) {
        const double f = areaFactor(p, n, skip, j);
        if (f == 0.0) continue;
        const double* B = &radiosity_[size_t(j) * size_t(bands_)];
        for (int band = 0; band < bands_; ++band) H[band] += f * B[band];
    }
}

}  // namespace metamer
