#include "radiosity/scene_radiosity.h"

#include "core/error.h"
#include "core/timing.h"
#include "radiosity/form_factor.h"
#include "radiosity/vertex_gather.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
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

// M(out, in): radiosity in band `out` per irradiance in band `in` (W·m⁻²·nm⁻¹ per W·m⁻²·nm⁻¹),
// π times the renderers' fluorescence radiance (reference/cpu_renderer.cpp's terms).
Eigen::MatrixXd reemission(const MaterialOnGrid& m, const SceneOnGrid& g) {
    const size_t n = g.wavelengths_nm.size();
    const double step = g.grid.step_nm;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(Eigen::Index(n), Eigen::Index(n));
    if (!m.fluorescent) return M;
    for (size_t out = 0; out < n; ++out)
        for (size_t in = 0; in < n; ++in)
            M(Eigen::Index(out), Eigen::Index(in)) =
                m.isMatrix() ? m.donaldson[in * n + out] * step
                             : m.quantum_yield * m.emission[out] / g.wavelengths_nm[out] * m.excitation[in] *
                                   g.wavelengths_nm[in] * step;
    return M;
}

}  // namespace

std::string SceneInterreflection::describe() const {
    return fmt::format("interreflection: {} elements, form factors {:.2f} s ({} near pairs, {} rays), {}, gathered "
                       "at the vertices in {:.2f} s; {:.2f} s in all",
                       elements, coupling.seconds, coupling.nearPairs, coupling.rays, solution.describe(), gatherSeconds,
                       totalSeconds);
}

SceneInterreflection solveInterreflection(const Scene& scene, const SceneOnGrid& g, const InterreflectionSettings& s) {
    const auto t0 = Clock::now();
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
            failInput(Where{scene.file.string(), "interreflection.max_elements"},
                      "the surfaces make more than {} elements of at most {} m ({} with {}), more than the {} allowed; "
                      "their form factors would take over {:.1f} GiB: give a longer \"element_size\" or raise "
                      "\"max_elements\"",
                      count, s.elementSize_m, count, mesh.name, s.maxElements,
                      double(count) * double(count) * 8.0 / 1073741824.0);
        };
        mi.elements = refineMesh(mesh.positions, mesh.indices, s.elementSize_m, s.maxElements);
        if (mi.elements.truncated) refuse(made + s.maxElements);
        made += mi.elements.triangles.size() * (mesh.closed ? 1 : 2);
        if (made > s.maxElements) refuse(made);
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
    const size_t n = sides.size();
    out.elements = n;
    std::vector<std::array<glm::dvec3, 3>> corners(n);
    std::vector<uint32_t> source(n);
    for (size_t i = 0; i < n; ++i) {
        corners[i] = sides[i].corners;
        source[i] = sides[i].source;
    }
    out.coupling = formFactorMatrix(corners, &bvh, source);

    // Every element's reflectance (its texture averaged over the rule's points) and what the
    // direct light makes it send.
    Problem p;
    p.formFactors = std::move(out.coupling.formFactors);
    p.emission = Eigen::MatrixXd::Zero(Eigen::Index(n), Eigen::Index(bands));
    std::vector<double> texel(bands), irradiance(bands);
    for (size_t i = 0; i < n; ++i) {
        const Side& e = sides[i];
        const MaterialOnGrid& mat = g.materials[e.material];
        const glm::dvec3 normal = polygonNormal(e.corners);
        p.area.push_back(polygonArea(e.corners));
        SurfaceResponse response{mat.diffuse, reemission(mat, g)};
        if (mat.diffuseTexture >= 0) {
            std::vector<double> mean(bands, 0.0);
            for (const auto& q : kRule) {
                g.textures[size_t(mat.diffuseTexture)].bilinear(q[0] * e.uv[0] + q[1] * e.uv[1] + q[2] * e.uv[2], texel.data());
                for (size_t b = 0; b < bands; ++b) mean[b] += q[3] * texel[b];
            }
            for (size_t b = 0; b < bands; ++b) response.reflectance[b] = std::clamp(response.reflectance[b] * mean[b], 0.0, 1.0);
        }
        // The direct irradiance, averaged over the rule's points: each light as the renderers
        // take it (reference/cpu_renderer.cpp, shade), shadows by rays through the BVH.
        std::fill(irradiance.begin(), irradiance.end(), 0.0);
        for (const auto& q : kRule) {
            const glm::dvec3 x = q[0] * e.corners[0] + q[1] * e.corners[1] + q[2] * e.corners[2];
            for (size_t l = 0; l < scene.lights.size(); ++l) {
                const Light& light = scene.lights[l];
                double geometric = 0.0;
                if (light.type == Light::Type::Ambient) {
                    geometric = 1.0;
                } else if (light.type == Light::Type::Hemisphere) {
                    geometric = kPi * (1.0 + glm::dot(normal, light.up)) / 2.0;
                } else {
                    glm::dvec3 w;
                    double falloff = 1.0, reach = std::numeric_limits<double>::infinity();
                    if (light.type == Light::Type::Directional) {
                        w = -glm::normalize(light.direction);
                    } else {
                        const glm::dvec3 d = light.position - x;
                        reach = glm::length(d);
                        if (!(reach > 0.0)) continue;
                        w = d / reach;
                        falloff = 1.0 / (reach * reach);
                    }
                    const double cosine = glm::dot(normal, w);
                    if (cosine <= 0.0) continue;
                    if (light.castsShadows() && bvh.occluded(Ray{x, w}, 1e-9, reach * (1.0 - 1e-12), e.source)) continue;
                    geometric = cosine * falloff;
                }
                for (size_t b = 0; b < bands; ++b) irradiance[b] += q[3] * geometric * g.lights[l][b];
            }
        }
        const Eigen::Map<const Eigen::VectorXd> H(irradiance.data(), Eigen::Index(bands));
        Eigen::VectorXd E = Eigen::Map<const Eigen::VectorXd>(response.reflectance.data(), Eigen::Index(bands)).cwiseProduct(H);
        if (mat.fluorescent) E += response.reemission * H;
        p.emission.row(Eigen::Index(i)) = E.transpose();
        // One surface per element (textures make each its own reflectance).
        p.surface.push_back(uint32_t(p.surfaces.size()));
        p.surfaces.push_back(std::move(response));
    }
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
