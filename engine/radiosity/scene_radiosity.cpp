#include "radiosity/scene_radiosity.h"

#include "core/error.h"
#include "core/timing.h"
#include "radiosity/form_factor.h"
#include "radiosity/geometry_cache.h"
#include "radiosity/product.h"
#include "radiosity/vertex_gather.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <span>

namespace metamer::radiosity {

namespace {

constexpr double kPi = std::numbers::pi;


// One side of one element: where it is, which way it faces, what it is made of.
struct Side {
    std::array<glm::dvec3, 3> corners;  // counter-clockwise seen from the side's front
    std::array<glm::dvec2, 3> uv{};
    uint32_t mesh = 0, material = 0, source = 0;  // source: its input triangle in the BVH
    bool back = false;
};

// What the solve takes of a reflectance: each band within [0, 1]. A reduced mode's channels can
// be negative (an rgb channel of a saturated colour), and a spectral ρ above 1 (warned about when
// read) would make the equation diverge; the direct light and the pixel's own ρ stay as they are.
std::vector<double> clampedReflectance(std::vector<double> rho) {
    for (double& r : rho) r = std::clamp(r, 0.0, 1.0);
    return rho;
}

// The solid angle of triangle t seen from o (Van Oosterom & Strackee 1983), sr.
double solidAngle(const std::array<glm::dvec3, 3>& t, const glm::dvec3& o) {
    const glm::dvec3 a = t[0] - o, b = t[1] - o, c = t[2] - o;
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double numerator = std::fabs(glm::dot(a, glm::cross(b, c)));
    const double denominator = la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
    return 2.0 * std::atan2(numerator, denominator);
}

}  // namespace

// M(out, in): radiosity in band `out` per irradiance in band `in` (W·m⁻²·nm⁻¹ per W·m⁻²·nm⁻¹),
// π times the renderers' fluorescence radiance (reference/cpu_renderer.cpp's terms).
Eigen::MatrixXd reemissionMatrix(const MaterialOnGrid& m, const SceneOnGrid& g) {
    if (!m.fluorescent) return {};
    const size_t n = g.wavelengths_nm.size();
    const double step = g.grid.step_nm;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(Eigen::Index(n), Eigen::Index(n));
    for (size_t out = 0; out < n; ++out)
        for (size_t in = 0; in < n; ++in)
            M(Eigen::Index(out), Eigen::Index(in)) =
                m.isMatrix() ? m.donaldson[in * n + out] * step
                             : m.quantum_yield * m.emission[out] / g.wavelengths_nm[out] * m.excitation[in] *
                                   g.wavelengths_nm[in] * step;
    return M;
}

std::string SceneInterreflection::describe() const {
    std::string refined;
    if (!refinement.empty()) {
        refined = ", refined";
        for (size_t r : refinement) refined += fmt::format(" +{}", r);
        if (refinementStopped) refined += " (stopped at max_elements)";
    }
    const std::string factors =
        formFactorsKept ? std::string(warmStart ? "form factors kept from the last render of the same geometry, its solve the start"
                                                : "form factors kept from the last render of the same geometry")
                        : fmt::format("form factors {:.2f} s ({} near pairs, {} rays in the last pass)", formFactorSeconds,
                                      coupling.nearPairs, coupling.rays);
    return fmt::format("interreflection: {} elements{}, {}, {} (tolerance {:g}), gathered at the vertices in {:.2f} s; {:.2f} s "
                       "in all",
                       elements, refined, factors, solution.describe(), tolerance, gatherSeconds, totalSeconds);
}

double elementSize(const Scene& scene) {
    if (scene.interreflection && scene.interreflection->elementSize_m) return *scene.interreflection->elementSize_m;
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const Mesh& m : scene.meshes) {
        if (scene.materials[m.material].isTransparent()) continue;
        for (const glm::dvec3& p : m.positions) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
    }
    const double diagonal = glm::all(glm::lessThanEqual(lo, hi)) ? glm::length(hi - lo) : 1.0;
    return diagonal > 0.0 ? diagonal / 24.0 : 1.0;
}

namespace {

// What n elements' form factors take: n² doubles, GiB (the refusals say it).
double formFactorGiB(double n) { return n * n * 8.0 / 1073741824.0; }

struct Settings {
    double elementSize_m, tolerance;
    size_t maxElements;
};

// The scene's opaque surfaces, as the BVH that occludes and each input triangle's place in it.
struct Occluders {
    const Bvh& bvh;
    const std::map<std::pair<uint32_t, uint32_t>, uint32_t>& index;  // (mesh, triangle) → BVH triangle
};

// H at the midpoints of a mesh's element edges, on each side: what refinement compares with the
// interpolation of H between the edge's ends.
struct EdgeMidpoints {
    std::vector<std::pair<uint32_t, uint32_t>> edges;  // each once, (a, b) with a < b
    Eigen::MatrixXd front, back;                       // [edge][band], as MeshInterreflection's
    Eigen::MatrixXd frontDirect, backDirect, frontUnoccluded, backUnoccluded;  // [edge][emitter]
    Eigen::MatrixXd frontBuried, backBuried;                                   // [edge][0]: 1 inside a solid
};

// Per gather point: H without the emitters' direct light, and per emitter D and U
// (MeshInterreflection). `emitterOf`: each element's emitter, −1 for none.
struct Gathered {
    Eigen::MatrixXd H, direct, unoccluded;
    Eigen::MatrixXd buried;  // [point][0]: 1 inside a closed solid (vertex_gather.h, buriedPoints)
};
Gathered gather(std::span<const GatherPoint> points, std::span<const std::array<glm::dvec3, 3>> corners, const Bvh& bvh,
                const Eigen::MatrixXd& radiosity, const std::vector<int>& emitterOf,
                const std::vector<EmitterGeometry>& emitters, const SceneOnGrid& g, const std::vector<char>& closed) {
    bool kept = false;  // from the geometry cache: the same points, elements and occluders
    const std::shared_ptr<const Eigen::MatrixXd> cached = cachedGatherFactors(points, corners, bvh, 0, kept);
    const Eigen::MatrixXd& W = *cached;
    Gathered out;
    const std::vector<char> buried = buriedPoints(points, bvh, closed);
    out.buried = Eigen::MatrixXd::Zero(Eigen::Index(points.size()), 1);
    for (size_t p = 0; p < points.size(); ++p) out.buried(Eigen::Index(p), 0) = buried[p];
    if (emitters.empty()) {
        out.H = timesOnEveryCore(W, radiosity);
        return out;
    }
    const Eigen::Index n = Eigen::Index(corners.size()), count = Eigen::Index(emitters.size());
    Eigen::MatrixXd bounced = radiosity;
    for (Eigen::Index j = 0; j < n; ++j)
        if (const int e = emitterOf[size_t(j)]; e >= 0) {
            const std::vector<double>& Le = g.materials[emitters[size_t(e)].material].emitted;
            for (Eigen::Index b = 0; b < bounced.cols(); ++b) bounced(j, b) -= kPi * Le[size_t(b)];
        }
    out.H = timesOnEveryCore(W, bounced);
    // D from the emitters' elements alone, each seen from 4 × 4 points on it (W's one centroid ray
    // flips from one vertex to the next across a shadow's edge; the pixels interpolate D/U).
    std::vector<std::array<glm::dvec3, 3>> emitting;
    std::vector<Eigen::Index> emittingRow;
    for (Eigen::Index j = 0; j < n; ++j)
        if (emitterOf[size_t(j)] >= 0) {
            emitting.push_back(corners[size_t(j)]);
            emittingRow.push_back(j);
        }
    bool keptSampled = false;
    const std::shared_ptr<const Eigen::MatrixXd> sampled = cachedGatherFactors(points, emitting, bvh, 4, keptSampled);
    Eigen::MatrixXd emitterShare = Eigen::MatrixXd::Zero(Eigen::Index(emitting.size()), count);
    for (size_t k = 0; k < emitting.size(); ++k) emitterShare(Eigen::Index(k), emitterOf[size_t(emittingRow[k])]) = 1.0;
    out.direct = *sampled * emitterShare;
    out.unoccluded = Eigen::MatrixXd::Zero(Eigen::Index(points.size()), count);
    for (size_t p = 0; p < points.size(); ++p) {
        // Where the gather evaluates the point (vertex_gather.cpp): a hair inside its own surface,
        // so that U at the foot of an emitting wall is the limit the pixels beside it approach.
        const glm::dvec3 x = points[p].position + 1e-7 * points[p].inside;
        for (size_t e = 0; e < emitters.size(); ++e)
            for (const auto& t : emitters[e].triangles)
                out.unoccluded(Eigen::Index(p), Eigen::Index(e)) += pointToTriangle(x, points[p].normal, t, polygonNormal(t));
    }
    return out;
}

// Rows of `values` not `known` take the mean of the known rows of the vertices they share an element
// with, spreading outwards pass by pass (a vertex deep under a box takes its edge's); a row with no
// known vertex in reach keeps its value.
void fillFromNeighbours(Eigen::MatrixXd& values, Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> known,
                        const ElementMesh& mesh) {
    for (int pass = 0; pass < 64 && !known.all(); ++pass) {
        Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(values.rows(), values.cols()), count = sum;
        for (const auto& t : mesh.triangles)
            for (uint32_t a : t)
                for (uint32_t b : t)
                    for (Eigen::Index c = 0; c < values.cols(); ++c)
                        if (a != b && !known(a, c) && known(b, c)) {
                            sum(a, c) += values(b, c);
                            count(a, c) += 1.0;
                        }
        if ((count.array() == 0.0).all()) break;
        for (Eigen::Index v = 0; v < values.rows(); ++v)
            for (Eigen::Index c = 0; c < values.cols(); ++c)
                if (count(v, c) > 0.0) {
                    values(v, c) = sum(v, c) / count(v, c);
                    known(v, c) = true;
                }
    }
}

// A buried vertex's H (it gathers nothing) is its unburied neighbours': the pixels on the visible
// part of its elements interpolate it.
void fillBuried(Eigen::MatrixXd& H, const Eigen::MatrixXd& buried, const ElementMesh& mesh) {
    if (H.rows() == 0 || !(buried.array() > 0.0).any()) return;
    fillFromNeighbours(H, (buried.col(0).array() == 0.0).replicate(1, H.cols()), mesh);
}

// Each vertex's share D/U of each emitter's direct light. Where the emitter sends nothing (U = 0: a
// wall's vertex at the height of a ceiling light's plane) or the vertex is buried, the share is
// undefined, yet the pixels beside it interpolate it: it takes its neighbours' (fillFromNeighbours),
// else 1 (nothing found in the way).
Eigen::MatrixXd emitterShares(const Eigen::MatrixXd& D, const Eigen::MatrixXd& U, const Eigen::MatrixXd& buried,
                              const ElementMesh& mesh) {
    constexpr double kReached = 1e-12;  // a form factor below this is no light at all
    Eigen::MatrixXd S = Eigen::MatrixXd::Ones(U.rows(), U.cols());
    Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> known(U.rows(), U.cols());
    for (Eigen::Index v = 0; v < U.rows(); ++v)
        for (Eigen::Index e = 0; e < U.cols(); ++e) {
            known(v, e) = U(v, e) > kReached && buried(v, 0) == 0.0;
            if (known(v, e)) S(v, e) = D(v, e) / U(v, e);
        }
    fillFromNeighbours(S, known, mesh);
    return S;
}

// Everything but the elements themselves, on out.meshes[·].elements as they are: the sides, their
// reflectance and direct light, the form factors, the solve and the vertices' H.
void solveOn(const Scene& scene, const SceneOnGrid& g, const Occluders& occluders, const Settings& s,
             SceneInterreflection& out, std::vector<EdgeMidpoints>* midpoints) {
    const Bvh& bvh = occluders.bvh;
    const auto& bvhIndex = occluders.index;
    const size_t bands = g.wavelengths_nm.size();
    // Sides: each refined mesh's front, and its back unless it is closed.
    std::vector<Side> sides;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        if (scene.materials[mesh.material].isTransparent()) continue;
        MeshInterreflection& mi = out.meshes[m];
        const std::vector<glm::dvec2> uvs =
            mesh.uvs.empty() ? std::vector<glm::dvec2>() : interpolate<glm::dvec2>(mi.elements, mesh.uvs);
        for (int side = 0; side < (mesh.closed ? 1 : 2); ++side)
            for (size_t t = 0; t < mi.elements.triangles.size(); ++t) {
                Side e;
                const auto& v = mi.elements.triangles[t];
                const std::array<uint32_t, 3> order = side == 0 ? v : std::array<uint32_t, 3>{v[0], v[2], v[1]};
                for (int k = 0; k < 3; ++k) {
                    e.corners[size_t(k)] = mi.elements.vertices[order[size_t(k)]];
                    if (!uvs.empty()) e.uv[size_t(k)] = uvs[order[size_t(k)]];
                }
                e.mesh = uint32_t(m);
                e.material = mesh.material;
                e.source = bvhIndex.at({uint32_t(m), mi.elements.inputTriangle[t]});
                e.back = side == 1;
                sides.push_back(e);
            }
    }
    // Every side's reflectance (its texture averaged over the rule's points) and what the direct
    // light makes it send.
    const size_t all = sides.size();
    std::vector<double> area(all);
    std::vector<int> surfaceOf(all);
    std::vector<SurfaceResponse> surfaces;
    std::vector<int> materialSurface(g.materials.size(), -1);  // untextured materials share one
    Eigen::MatrixXd emission = Eigen::MatrixXd::Zero(Eigen::Index(all), Eigen::Index(bands));
    std::vector<double> texel(bands), irradiance(bands);
    for (size_t i = 0; i < all; ++i) {
        const Side& e = sides[i];
        const MaterialOnGrid& mat = g.materials[e.material];
        const glm::dvec3 normal = polygonNormal(e.corners);
        area[i] = polygonArea(e.corners);
        if (mat.diffuseTexture >= 0) {
            SurfaceResponse response{clampedReflectance(mat.diffuse), {}};  // textured fluorescent ones are refused when read
            std::vector<double> mean(bands, 0.0);
            for (const auto& q : kTriangleRule) {
                g.textures[size_t(mat.diffuseTexture)].bilinear(q.a * e.uv[0] + q.b * e.uv[1] + q.c * e.uv[2], texel.data());
                for (size_t b = 0; b < bands; ++b) mean[b] += q.w * texel[b];
            }
            for (size_t b = 0; b < bands; ++b) response.reflectance[b] = std::clamp(response.reflectance[b] * mean[b], 0.0, 1.0);
            surfaceOf[i] = int(surfaces.size());
            surfaces.push_back(std::move(response));
        } else {
            if (materialSurface[e.material] < 0) {
                materialSurface[e.material] = int(surfaces.size());
                surfaces.push_back(SurfaceResponse{clampedReflectance(mat.diffuse), reemissionMatrix(mat, g)});
            }
            surfaceOf[i] = materialSurface[e.material];
        }
        const SurfaceResponse& response = surfaces[size_t(surfaceOf[i])];
        // The direct irradiance averaged over the element: each light as the renderers take it
        // (reference/cpu_renderer.cpp, shade), shadows by rays through the BVH from the rule's
        // points. A point light's unoccluded average is exact, I·Ω/A (Ω the element's solid angle
        // from the light: ∫ cos θ/d² dA), where a surface near the light peaks far too sharply for
        // a rule: times the share of the rule's points it reaches.
        std::fill(irradiance.begin(), irradiance.end(), 0.0);
        for (size_t l = 0; l < scene.lights.size(); ++l) {
            const Light& light = scene.lights[l];
            if (light.type != Light::Type::Point || !(glm::dot(normal, light.position - e.corners[0]) > 0.0)) continue;
            double reached = 0.0;
            for (const auto& q : kTriangleRule) {
                const glm::dvec3 x = q.on(e.corners);
                const glm::dvec3 d = light.position - x;
                const double reach = glm::length(d);
                if (reach > 0.0 && (!light.castsShadows() || !bvh.occluded(Ray{x, d / reach}, 1e-9, reach * (1.0 - 1e-12), e.source)))
                    reached += q.w;
            }
            const double average = solidAngle(e.corners, light.position) / area[i] * reached;
            for (size_t b = 0; b < bands; ++b) irradiance[b] += average * g.lights[l][b];
        }
        for (const auto& q : kTriangleRule) {
            const glm::dvec3 x = q.on(e.corners);
            for (size_t l = 0; l < scene.lights.size(); ++l) {
                const Light& light = scene.lights[l];
                double geometric = 0.0;
                if (light.type == Light::Type::Ambient) {
                    geometric = 1.0;
                } else if (light.type == Light::Type::Hemisphere) {
                    geometric = kPi * (1.0 + glm::dot(normal, light.up)) / 2.0;
                } else if (light.type == Light::Type::Directional) {
                    const glm::dvec3 w = -glm::normalize(light.direction);
                    const double cosine = glm::dot(normal, w);
                    if (cosine <= 0.0) continue;
                    if (light.castsShadows() && bvh.occluded(Ray{x, w}, 1e-9, std::numeric_limits<double>::infinity(), e.source))
                        continue;
                    geometric = cosine;
                } else {
                    continue;  // point lights: above
                }
                for (size_t b = 0; b < bands; ++b) irradiance[b] += q.w * geometric * g.lights[l][b];
            }
        }
        const Eigen::Map<const Eigen::VectorXd> H(irradiance.data(), Eigen::Index(bands));
        Eigen::VectorXd E = Eigen::Map<const Eigen::VectorXd>(response.reflectance.data(), Eigen::Index(bands)).cwiseProduct(H);
        if (response.reemission.size() != 0) E += response.reemission * H;
        // A self-luminous surface's front sends π·L_e besides (the exitance of a Lambertian emitter).
        if (mat.isEmitter() && !e.back)
            for (size_t b = 0; b < bands; ++b) E[Eigen::Index(b)] += kPi * mat.emitted[b];
        emission.row(Eigen::Index(i)) = E.transpose();
    }
    // A side that the direct light does not reach, and in front of which no other element lies
    // (a room's walls seen from outside), neither receives nor sends anything: left out.
    // The box around every corner answers for most outward sides at once: its corners all behind
    // a side's plane put every element there.
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const Side& e : sides)
        for (const glm::dvec3& c : e.corners) {
            lo = glm::min(lo, c);
            hi = glm::max(hi, c);
        }
    std::vector<size_t> kept;
    for (size_t i = 0; i < all; ++i) {
        bool useful = emission.row(Eigen::Index(i)).cwiseAbs().maxCoeff() > 0.0;
        const glm::dvec3 normal = polygonNormal(sides[i].corners);
        const double slack = 1e-12 * std::sqrt(area[i]);
        // The box's corner farthest along the normal, its height above the plane.
        const glm::dvec3 farthest(normal.x > 0.0 ? hi.x : lo.x, normal.y > 0.0 ? hi.y : lo.y, normal.z > 0.0 ? hi.z : lo.z);
        const bool boxBehind = !(glm::dot(normal, farthest - sides[i].corners[0]) > slack);
        for (size_t j = 0; j < all && !useful && !boxBehind; ++j)
            for (const glm::dvec3& c : sides[j].corners)
                if (j != i && glm::dot(normal, c - sides[i].corners[0]) > slack) {
                    useful = true;
                    break;
                }
        if (useful) kept.push_back(i);
    }
    const size_t n = kept.size();
    out.elements = n;
    if (n > s.maxElements)
        failInput(scene.interreflection->where.child("max_elements"),
                  "the surfaces make {} elements of at most {:.4g} m that take part, more than the {} allowed; their form "
                  "factors would take {:.1f} GiB: give a longer \"element_size\" or raise \"max_elements\"",
                  n, s.elementSize_m, s.maxElements, formFactorGiB(double(n)));
    std::vector<std::array<glm::dvec3, 3>> corners(n);
    std::vector<uint32_t> source(n);
    Problem p;
    p.emission = Eigen::MatrixXd(Eigen::Index(n), Eigen::Index(bands));
    for (size_t k = 0; k < n; ++k) {
        corners[k] = sides[kept[k]].corners;
        source[k] = sides[kept[k]].source;
        p.area.push_back(area[kept[k]]);
        p.surface.push_back(uint32_t(surfaceOf[kept[k]]));
        p.emission.row(Eigen::Index(k)) = emission.row(Eigen::Index(kept[k]));
    }
    p.surfaces = std::move(surfaces);
    out.area = p.area;
    // The elements on the front of each emitter drawn per pixel.
    std::vector<int> emitterOf(n, -1);
    for (size_t k = 0; k < n; ++k)
        for (size_t e = 0; e < out.emitters.size(); ++e)
            if (!sides[kept[k]].back && sides[kept[k]].material == out.emitters[e].material) emitterOf[k] = int(e);
    bool cached = false;
    const std::shared_ptr<const Coupling> coupling = cachedFormFactors(corners, bvh, source, cached);
    out.coupling = Coupling{Eigen::MatrixXd(), coupling->nearPairs, coupling->rays, coupling->blockedRays,
                            cached ? 0.0 : coupling->seconds};
    out.formFactorsKept = cached;
    out.formFactorSeconds += out.coupling.seconds;
    p.sharedFormFactors = std::shared_ptr<const Eigen::MatrixXd>(coupling, &coupling->formFactors);  // read in place
    // On kept form factors: the last solve on them rescaled, when only the emission changed and by
    // a factor per band (one light's spectrum or scale, an emitter's); else a solve that starts from
    // it, each band scaled by how much its emission changed (least squares).
    const std::optional<LastSolve> before = lastSolveOn(*coupling);
    std::optional<Solution> rescaled;
    if (before) rescaled = rescaledSolution(before->problem, before->solution, p);
    if (rescaled && !(rescaled->relativeBound <= s.tolerance)) rescaled.reset();  // a tighter tolerance asked now
    if (rescaled) {
        out.solution = std::move(*rescaled);
    } else {
        std::optional<Eigen::MatrixXd> guess;
        if (before && before->problem.emission.rows() == p.emission.rows() &&
            before->problem.emission.cols() == p.emission.cols()) {
            guess = before->solution.radiosity;
            for (Eigen::Index b = 0; b < p.emission.cols(); ++b) {
                const double norm = before->problem.emission.col(b).squaredNorm();
                guess->col(b) *= norm > 0.0 ? p.emission.col(b).dot(before->problem.emission.col(b)) / norm : 0.0;
            }
        }
        out.warmStart = guess.has_value();
        out.solution = solve(p, s.tolerance, 2000, guess ? &*guess : nullptr);
    }
    keepLastSolve(coupling, LastSolve{p, out.solution});

    // The indirect irradiance at every element vertex, on each side.
    const auto tg = Clock::now();
    std::vector<GatherPoint> points;
    std::vector<std::pair<size_t, int>> owner, edgeOwner;  // (mesh, sides) of each mesh's points, in order
    std::vector<GatherPoint> edgePoints;
    for (size_t m = 0; m < out.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        const ElementMesh& em = out.meshes[m].elements;
        if (em.triangles.empty()) continue;
        std::vector<glm::dvec3> normals = mesh.normals.empty() ? std::vector<glm::dvec3>()
                                                                : interpolate<glm::dvec3>(em, mesh.normals);
        // Per vertex: the mean of its elements' centroids (where "inside" points), a face normal
        // where the mesh has none, and one of its triangles (which its rays skip).
        std::vector<glm::dvec3> centroidSum(em.vertices.size(), glm::dvec3(0.0)), faceNormal(em.vertices.size(), glm::dvec3(0.0));
        std::vector<uint32_t> anyTriangle(em.vertices.size(), 0), uses(em.vertices.size(), 0);
        for (size_t t = 0; t < em.triangles.size(); ++t)
            for (uint32_t v : em.triangles[t]) {
                ++uses[v];
                centroidSum[v] += em.centroid(t);
                faceNormal[v] += em.normal(t) * em.area(t);
                anyTriangle[v] = bvhIndex.at({uint32_t(m), em.inputTriangle[t]});
            }
        auto unitNormal = [&](size_t v) {
            const glm::dvec3 normal = normals.empty() ? faceNormal[v] : normals[v];
            const double length = glm::length(normal);
            return length > 0.0 ? normal / length : glm::dvec3(0.0, 0.0, 1.0);
        };
        for (int side = 0; side < (mesh.closed ? 1 : 2); ++side)
            for (size_t v = 0; v < em.vertices.size(); ++v) {
                GatherPoint gp;
                gp.position = em.vertices[v];
                gp.normal = side == 0 ? unitNormal(v) : -unitNormal(v);
                gp.inside = uses[v] > 0 ? centroidSum[v] / double(uses[v]) - em.vertices[v] : glm::dvec3(0.0);
                gp.source = anyTriangle[v];
                points.push_back(gp);
            }
        owner.push_back({m, mesh.closed ? 1 : 2});
        if (midpoints) {
            // Each edge's midpoint, a hair into one of its triangles.
            EdgeMidpoints& e = (*midpoints)[m];
            e = {};
            std::map<std::pair<uint32_t, uint32_t>, uint32_t> triangleOf;
            for (size_t t = 0; t < em.triangles.size(); ++t)
                for (int k = 0; k < 3; ++k) {
                    const uint32_t a = em.triangles[t][size_t(k)], b = em.triangles[t][size_t((k + 1) % 3)];
                    triangleOf.emplace(std::pair{std::min(a, b), std::max(a, b)}, uint32_t(t));
                }
            for (const auto& [edge, t] : triangleOf) e.edges.push_back(edge);
            for (int side = 0; side < (mesh.closed ? 1 : 2); ++side)
                for (const auto& [edge, t] : triangleOf) {
                    const auto [a, b] = edge;
                    GatherPoint gp;
                    gp.position = 0.5 * (em.vertices[a] + em.vertices[b]);
                    const glm::dvec3 normal = glm::normalize(unitNormal(a) + unitNormal(b));
                    gp.normal = side == 0 ? normal : -normal;
                    gp.inside = em.centroid(t) - gp.position;
                    gp.source = bvhIndex.at({uint32_t(m), em.inputTriangle[t]});
                    edgePoints.push_back(gp);
                }
            edgeOwner.push_back({m, mesh.closed ? 1 : 2});
        }
    }
    // Rows of a gathered matrix to each mesh's sides, in the order the points were made.
    auto split = [](const Eigen::MatrixXd& all, Eigen::Index& row, Eigen::Index count, int sidesOfMesh,
                    Eigen::MatrixXd& front, Eigen::MatrixXd& back) {
        if (all.size() == 0) return;
        front = all.middleRows(row, count);
        if (sidesOfMesh == 2) back = all.middleRows(row + count, count);
        row += count * sidesOfMesh;
    };
    std::vector<char> closed(scene.meshes.size());
    for (size_t m = 0; m < scene.meshes.size(); ++m) closed[m] = scene.meshes[m].closed;
    const Gathered at = gather(points, corners, bvh, out.solution.radiosity, emitterOf, out.emitters, g, closed);
    Eigen::Index rows[4] = {0, 0, 0, 0};
    for (const auto& [m, sidesOfMesh] : owner) {
        MeshInterreflection& mi = out.meshes[m];
        const Eigen::Index count = Eigen::Index(mi.elements.vertices.size());
        split(at.H, rows[0], count, sidesOfMesh, mi.front, mi.back);
        split(at.direct, rows[1], count, sidesOfMesh, mi.frontDirect, mi.backDirect);
        split(at.unoccluded, rows[2], count, sidesOfMesh, mi.frontUnoccluded, mi.backUnoccluded);
        Eigen::MatrixXd frontBuried, backBuried;
        split(at.buried, rows[3], count, sidesOfMesh, frontBuried, backBuried);
        fillBuried(mi.front, frontBuried, mi.elements);
        if (sidesOfMesh == 2) fillBuried(mi.back, backBuried, mi.elements);
        if (!out.emitters.empty()) {
            mi.frontShare = emitterShares(mi.frontDirect, mi.frontUnoccluded, frontBuried, mi.elements);
            if (sidesOfMesh == 2) mi.backShare = emitterShares(mi.backDirect, mi.backUnoccluded, backBuried, mi.elements);
        }
    }
    if (midpoints) {
        const Gathered mid = gather(edgePoints, corners, bvh, out.solution.radiosity, emitterOf, out.emitters, g, closed);
        std::fill(rows, rows + 4, 0);
        for (const auto& [m, sidesOfMesh] : edgeOwner) {
            EdgeMidpoints& e = (*midpoints)[m];
            const Eigen::Index count = Eigen::Index(e.edges.size());
            split(mid.H, rows[0], count, sidesOfMesh, e.front, e.back);
            split(mid.direct, rows[1], count, sidesOfMesh, e.frontDirect, e.backDirect);
            split(mid.unoccluded, rows[2], count, sidesOfMesh, e.frontUnoccluded, e.backUnoccluded);
            split(mid.buried, rows[3], count, sidesOfMesh, e.frontBuried, e.backBuried);
        }
    }
    out.gatherSeconds += msSince(tg) / 1000.0;
}

// How far the renderer's reconstruction along edge k of a mesh — H interpolated, plus each
// emitter's πL_e × its share interpolated × U at the point — misses what is gathered at the edge's
// midpoint, Σ over bands, and that value's own Σ: the larger of the mesh's two sides.
std::pair<double, double> interpolationMiss(const MeshInterreflection& mi, const EdgeMidpoints& e, size_t k,
                                            const std::vector<EmitterGeometry>& emitters, const SceneOnGrid& g) {
    const auto [a, b] = e.edges[k];
    const Eigen::Index ia = Eigen::Index(a), ib = Eigen::Index(b), ik = Eigen::Index(k);
    auto miss = [&](const Eigen::MatrixXd& H, const Eigen::MatrixXd& mid, const Eigen::MatrixXd& S, const Eigen::MatrixXd& Dm,
                    const Eigen::MatrixXd& Um, const Eigen::MatrixXd& buried) -> std::pair<double, double> {
        if (buried(ik, 0) != 0.0) return {0.0, 0.0};  // no pixel sees it
        Eigen::RowVectorXd actual = mid.row(ik), predicted = 0.5 * (H.row(ia) + H.row(ib));
        for (size_t em = 0; em < emitters.size(); ++em) {
            const Eigen::Index c = Eigen::Index(em);
            const double shared = 0.5 * (S(ia, c) + S(ib, c));
            const std::vector<double>& Le = g.materials[emitters[em].material].emitted;
            for (Eigen::Index band = 0; band < actual.size(); ++band) {
                actual[band] += kPi * Le[size_t(band)] * Dm(ik, c);
                predicted[band] += kPi * Le[size_t(band)] * shared * Um(ik, c);
            }
        }
        return {(actual - predicted).cwiseAbs().sum(), actual.cwiseAbs().sum()};
    };
    std::pair<double, double> worst =
        miss(mi.front, e.front, mi.frontShare, e.frontDirect, e.frontUnoccluded, e.frontBuried);
    if (e.back.rows() > 0) {
        const std::pair<double, double> back =
            miss(mi.back, e.back, mi.backShare, e.backDirect, e.backUnoccluded, e.backBuried);
        if (back.first > worst.first) worst = back;
    }
    return worst;
}

}  // namespace

SceneInterreflection solveInterreflection(const Scene& scene, const SceneOnGrid& g) {
    const auto t0 = Clock::now();
    if (!scene.interreflection) failRuntime("solveInterreflection: the scene asks for no interreflection");
    const Interreflection& settings = *scene.interreflection;
    const Settings s{elementSize(scene), settings.tolerance, size_t(settings.maxElements)};
    SceneInterreflection out;
    out.tolerance = settings.tolerance;
    out.meshes.resize(scene.meshes.size());
    // The opaque surfaces occlude; the BVH's order is its own, so find each input triangle in it.
    const Bvh bvh(Bvh::collectTriangles(scene, LocalFrame{}, [&](const Mesh& m) {
        return !scene.materials[m.material].isTransparent();
    }));
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> bvhIndex;
    for (uint32_t i = 0; i < bvh.triangles().size(); ++i)
        bvhIndex[{bvh.triangles()[i].mesh, bvh.triangles()[i].triangle}] = i;

    // Elements: each opaque mesh bisected to the element size; both sides of an open one count.
    size_t made = 0;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        if (scene.materials[mesh.material].isTransparent()) continue;
        MeshInterreflection& mi = out.meshes[m];
        auto refuse = [&](size_t count) {
            failInput(settings.where.child("max_elements"),
                      "the surfaces make more than {} elements of at most {:.4g} m ({} with {}), more than the {} allowed; "
                      "their form factors would take over {:.1f} GiB: give a longer \"element_size\" or raise "
                      "\"max_elements\"",
                      count, s.elementSize_m, count, mesh.name, s.maxElements, formFactorGiB(double(count)));
        };
        mi.elements = refineMesh(mesh.positions, mesh.indices, s.elementSize_m, s.maxElements);
        if (mi.elements.truncated) refuse(made + s.maxElements);
        made += mi.elements.triangles.size() * (mesh.closed ? 1 : 2);
    }
    // The emitters whose direct light the renderer draws per pixel: their front triangles.
    size_t emitterTriangles = 0;
    for (size_t mat = 0; mat < g.materials.size(); ++mat) {
        if (!g.materials[mat].isEmitter()) continue;
        EmitterGeometry e;
        e.material = uint32_t(mat);
        for (const Mesh& mesh : scene.meshes)
            if (mesh.material == mat)
                for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
                    e.triangles.push_back({mesh.positions[mesh.indices[t]], mesh.positions[mesh.indices[t + 1]],
                                           mesh.positions[mesh.indices[t + 2]]});
        emitterTriangles += e.triangles.size();
        if (!e.triangles.empty()) out.emitters.push_back(std::move(e));
    }
    if (out.emitters.size() > kMaxPixelEmitters || emitterTriangles > kMaxPixelEmitterTriangles) out.emitters.clear();
    const Occluders occluders{bvh, bvhIndex};
    std::vector<EdgeMidpoints> midpoints(scene.meshes.size());
    solveOn(scene, g, occluders, s, out, settings.refine > 0 ? &midpoints : nullptr);

    // Refinement where the indirect light changes fast: an element edge whose linear interpolation
    // of H misses H gathered at its midpoint by more than refine_threshold of that H (Σ over bands;
    // where H is at least 10⁻³ of the mean vertex H) is bisected, down to an element size / 16, and
    // the whole solved again; at most `refine` times, and within max_elements (a pass that would
    // exceed them refines no more and says so).
    const double minEdge2 = std::pow(s.elementSize_m / 16.0, 2);
    for (int pass = 0; pass < settings.refine; ++pass) {
        double sum = 0.0;
        size_t count = 0;
        for (const MeshInterreflection& mi : out.meshes) {
            sum += mi.front.sum() + mi.back.sum();
            count += size_t(mi.front.rows() + mi.back.rows());
        }
        const double floor = 1e-3 * (count > 0 ? sum / double(count) : 0.0);
        if (!(floor > 0.0)) break;
        size_t added = 0, budget = s.maxElements > out.elements ? s.maxElements - out.elements : 0;
        bool stopped = false;
        for (size_t m = 0; m < scene.meshes.size() && !stopped; ++m) {
            MeshInterreflection& mi = out.meshes[m];
            if (mi.elements.triangles.empty()) continue;
            std::vector<std::pair<uint32_t, uint32_t>> edges;
            const EdgeMidpoints& e = midpoints[m];
            for (size_t k = 0; k < e.edges.size(); ++k) {
                const auto [a, b] = e.edges[k];
                const glm::dvec3 d = mi.elements.vertices[a] - mi.elements.vertices[b];
                if (!(glm::dot(d, d) > minEdge2)) continue;
                const auto [miss, at] = interpolationMiss(mi, e, k, out.emitters, g);
                if (at > floor && miss > settings.refineThreshold * at) edges.push_back({a, b});
            }
            if (edges.empty()) continue;
            const size_t sidesPer = scene.meshes[m].closed ? 1 : 2;
            const size_t before = mi.elements.triangles.size();
            mi.elements.truncated = false;
            refineEdges(mi.elements, edges, before + budget / sidesPer);
            const size_t grown = (mi.elements.triangles.size() - before) * sidesPer;
            added += grown;
            budget -= std::min(budget, grown);
            stopped = mi.elements.truncated;
            mi.elements.truncated = false;
        }
        out.refinement.push_back(added);
        out.refinementStopped = stopped;
        if (added == 0) break;
        out.coupling = {};
        solveOn(scene, g, occluders, s, out, pass + 1 < settings.refine ? &midpoints : nullptr);
    }
    out.totalSeconds = msSince(t0) / 1000.0;
    return out;
}

}  // namespace metamer::radiosity
