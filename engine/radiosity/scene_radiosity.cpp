#include "radiosity/scene_radiosity.h"

#include "core/error.h"
#include "core/timing.h"
#include "radiosity/form_factor.h"
#include "radiosity/vertex_gather.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace metamer::radiosity {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The 7-point degree-5 rule's barycentric points and weights (form_factor.cpp's).
constexpr double kA1 = 0.059715871789769820, kB1 = 0.470142064105115090, kW1 = 0.132394152788506181;
constexpr double kA2 = 0.797426985353087322, kB2 = 0.101286507323456339, kW2 = 0.125939180544827153;
constexpr std::array<std::array<double, 4>, 7> kRule = {{{1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, 0.225},
                                                         {kA1, kB1, kB1, kW1},
                                                         {kB1, kA1, kB1, kW1},
                                                         {kB1, kB1, kA1, kW1},
                                                         {kA2, kB2, kB2, kW2},
                                                         {kB2, kA2, kB2, kW2},
                                                         {kB2, kB2, kA2, kW2}}};

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
    return fmt::format("interreflection: {} elements, form factors {:.2f} s ({} near pairs, {} rays), {}, gathered "
                       "at the vertices in {:.2f} s; {:.2f} s in all",
                       elements, coupling.seconds, coupling.nearPairs, coupling.rays, solution.describe(), gatherSeconds,
                       totalSeconds);
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

SceneInterreflection solveInterreflection(const Scene& scene, const SceneOnGrid& g) {
    const auto t0 = Clock::now();
    if (!scene.interreflection) failRuntime("solveInterreflection: the scene asks for no interreflection");
    struct {
        double elementSize_m, tolerance;
        size_t maxElements;
    } const s{elementSize(scene), scene.interreflection->tolerance, size_t(scene.interreflection->maxElements)};
    SceneInterreflection out;
    out.meshes.resize(scene.meshes.size());
    const size_t bands = g.wavelengths_nm.size();
    // The opaque surfaces occlude; the BVH's order is its own, so find each input triangle in it.
    const Bvh bvh(Bvh::collectTriangles(scene, LocalFrame{}, [&](const Mesh& m) {
        return !scene.materials[m.material].isTransparent();
    }));
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> bvhIndex;
    for (uint32_t i = 0; i < bvh.triangles().size(); ++i)
        bvhIndex[{bvh.triangles()[i].mesh, bvh.triangles()[i].triangle}] = i;

    // Elements: each opaque mesh refined; its front, and its back unless it is closed.
    std::vector<Side> sides;
    size_t made = 0;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        if (scene.materials[mesh.material].isTransparent()) continue;
        MeshInterreflection& mi = out.meshes[m];
        auto refuse = [&](size_t count) {
            failInput(scene.interreflection->where.child("max_elements"),
                      "the surfaces make more than {} elements of at most {:.4g} m ({} with {}), more than the {} allowed; "
                      "their form factors would take over {:.1f} GiB: give a longer \"element_size\" or raise "
                      "\"max_elements\"",
                      count, s.elementSize_m, count, mesh.name, s.maxElements,
                      double(count) * double(count) * 8.0 / 1073741824.0);
        };
        mi.elements = refineMesh(mesh.positions, mesh.indices, s.elementSize_m, s.maxElements);
        if (mi.elements.truncated) refuse(made + s.maxElements);
        made += mi.elements.triangles.size();
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
            for (const auto& q : kRule) {
                g.textures[size_t(mat.diffuseTexture)].bilinear(q[0] * e.uv[0] + q[1] * e.uv[1] + q[2] * e.uv[2], texel.data());
                for (size_t b = 0; b < bands; ++b) mean[b] += q[3] * texel[b];
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
            for (const auto& q : kRule) {
                const glm::dvec3 x = q[0] * e.corners[0] + q[1] * e.corners[1] + q[2] * e.corners[2];
                const glm::dvec3 d = light.position - x;
                const double reach = glm::length(d);
                if (reach > 0.0 && (!light.castsShadows() || !bvh.occluded(Ray{x, d / reach}, 1e-9, reach * (1.0 - 1e-12), e.source)))
                    reached += q[3];
            }
            const double average = solidAngle(e.corners, light.position) / area[i] * reached;
            for (size_t b = 0; b < bands; ++b) irradiance[b] += average * g.lights[l][b];
        }
        for (const auto& q : kRule) {
            const glm::dvec3 x = q[0] * e.corners[0] + q[1] * e.corners[1] + q[2] * e.corners[2];
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
                for (size_t b = 0; b < bands; ++b) irradiance[b] += q[3] * geometric * g.lights[l][b];
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
    std::vector<size_t> kept;
    for (size_t i = 0; i < all; ++i) {
        bool useful = emission.row(Eigen::Index(i)).cwiseAbs().maxCoeff() > 0.0;
        const glm::dvec3 normal = polygonNormal(sides[i].corners);
        const double slack = 1e-12 * std::sqrt(area[i]);
        for (size_t j = 0; j < all && !useful; ++j)
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
                  n, s.elementSize_m, s.maxElements, double(n) * double(n) * 8.0 / 1073741824.0);
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
    out.coupling = formFactorMatrix(corners, &bvh, source);
    p.formFactors = std::move(out.coupling.formFactors);
    out.solution = solve(p, s.tolerance);

    // The indirect irradiance at every element vertex, on each side.
    const auto tg = Clock::now();
    std::vector<GatherPoint> points;
    std::vector<std::pair<size_t, int>> owner;  // (mesh, side) of each point, in order
    for (size_t m = 0; m < out.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        const ElementMesh& em = out.meshes[m].elements;
        if (em.triangles.empty()) continue;
        std::vector<glm::dvec3> normals = mesh.normals.empty() ? std::vector<glm::dvec3>()
                                                                : interpolate<glm::dvec3>(em, mesh.normals);
        // Per vertex: the mean of its elements' centroids (where "inside" points), a face normal
        // where the mesh has none, and one of its triangles (which its rays skip).
        std::vector<glm::dvec3> centroidSum(em.vertices.size(), glm::dvec3(0.0)), faceNormal(em.vertices.size(), glm::dvec3(0.0));
        std::vector<uint32_t> anyTriangle(em.vertices.size(), 0);
        for (size_t t = 0; t < em.triangles.size(); ++t)
            for (uint32_t v : em.triangles[t]) {
                centroidSum[v] += em.centroid(t);
                faceNormal[v] += em.normal(t) * em.area(t);
                anyTriangle[v] = bvhIndex.at({uint32_t(m), em.inputTriangle[t]});
            }
        for (int side = 0; side < (mesh.closed ? 1 : 2); ++side)
            for (size_t v = 0; v < em.vertices.size(); ++v) {
                glm::dvec3 normal = normals.empty() ? faceNormal[v] : normals[v];
                const double length = glm::length(normal);
                normal = length > 0.0 ? normal / length : glm::dvec3(0.0, 0.0, 1.0);
                GatherPoint gp;
                gp.position = em.vertices[v];
                gp.normal = side == 0 ? normal : -normal;
                const double uses = double(std::count_if(em.triangles.begin(), em.triangles.end(), [&](const auto& t) {
                    return t[0] == v || t[1] == v || t[2] == v;
                }));
                gp.inside = uses > 0 ? centroidSum[v] / uses - em.vertices[v] : glm::dvec3(0.0);
                gp.source = anyTriangle[v];
                points.push_back(gp);
            }
        owner.push_back({m, mesh.closed ? 1 : 2});
    }
    const Eigen::MatrixXd W = gatherFactors(points, corners, &bvh);
    const Eigen::MatrixXd H = W * out.solution.radiosity;
    Eigen::Index row = 0;
    for (const auto& [m, sidesOfMesh] : owner) {
        const Eigen::Index count = Eigen::Index(out.meshes[m].elements.vertices.size());
        out.meshes[m].front = H.middleRows(row, count);
        row += count;
        if (sidesOfMesh == 2) {
            out.meshes[m].back = H.middleRows(row, count);
            row += count;
        }
    }
    out.gatherSeconds = msSince(tg) / 1000.0;
    out.totalSeconds = msSince(t0) / 1000.0;
    return out;
}

}  // namespace metamer::radiosity
