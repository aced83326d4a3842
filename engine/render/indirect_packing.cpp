// Interreflection's geometry and indirect light for the spectral pass (declared in
// render/spectral_packing.h, which says what they are). Tests: tests/interreflection_test.cpp.
#include "render/spectral_packing.h"

#include "core/error.h"
#include "radiosity/element_mesh.h"

#include <cmath>
#include <numbers>

namespace metamer {

namespace {

constexpr double kInvPi = std::numbers::inv_pi, kPi = std::numbers::pi;

}  // namespace

void packIndirectMesh(PackedScene& p, std::vector<IndirectVertex>& perVertex, const Scene& scene, const SceneOnGrid& g,
                      const LocalFrame& frame, size_t m, const radiosity::SceneInterreflection& interreflection) {
    const radiosity::MeshInterreflection& elements = interreflection.meshes[m];
    const auto& emitters = interreflection.emitters;
    const Mesh& mesh = scene.meshes[m];
    const radiosity::ElementMesh& em = elements.elements;
    const MaterialOnGrid& material = g.materials[mesh.material];
    const size_t bands = g.wavelengths_nm.size();
    // The mesh's attributes on the element vertices; without normals, each vertex takes its
    // elements' area-weighted face normal (a flat mesh's own).
    std::vector<glm::dvec3> normals;
    if (mesh.normals.size() == mesh.positions.size()) {
        normals = radiosity::interpolate<glm::dvec3>(em, mesh.normals);
    } else {
        normals.assign(em.vertices.size(), glm::dvec3(0.0));
        for (size_t t = 0; t < em.triangles.size(); ++t)
            for (uint32_t v : em.triangles[t]) normals[v] += em.normal(t) * em.area(t);
    }
    for (glm::dvec3& n : normals) {
        const double length = glm::length(n);
        n = length > 0.0 ? n / length : glm::dvec3(0.0);
    }
    const std::vector<glm::dvec2> uvs =
        mesh.uvs.empty() ? std::vector<glm::dvec2>() : radiosity::interpolate<glm::dvec2>(em, mesh.uvs);
    const std::vector<glm::dvec4> tangents =
        mesh.tangents.empty() ? std::vector<glm::dvec4>() : radiosity::interpolate<glm::dvec4>(em, mesh.tangents);
    // What the fragment adds per unit of its own ρd (H/π) and each emitter's share of its direct
    // light, or a fluorescent surface's whole radiance, the emitters' direct light included.
    const Eigen::MatrixXd M = material.fluorescent ? radiosity::reemissionMatrix(material, g) : Eigen::MatrixXd();
    auto radiance = [&](int side, size_t v) {
        const Eigen::MatrixXd& H = side == 0 ? elements.front : elements.back;
        const Eigen::MatrixXd& D = side == 0 ? elements.frontDirect : elements.backDirect;
        const Eigen::MatrixXd& S = side == 0 ? elements.frontShare : elements.backShare;
        IndirectVertex out;
        out.bands.resize(bands);
        Eigen::VectorXd h = H.row(Eigen::Index(v)).transpose();
        for (size_t e = 0; e < emitters.size(); ++e) {
            if (material.fluorescent) {
                const std::vector<double>& Le = g.materials[emitters[e].material].emitted;
                for (size_t b = 0; b < bands; ++b) h[Eigen::Index(b)] += kPi * Le[b] * D(Eigen::Index(v), Eigen::Index(e));
            } else {
                out.share[int(e)] = float(S(Eigen::Index(v), Eigen::Index(e)));
            }
        }
        const Eigen::VectorXd fluoresced = material.fluorescent ? Eigen::VectorXd(M * h) : Eigen::VectorXd();
        for (size_t b = 0; b < bands; ++b) {
            const double value = material.fluorescent ? material.diffuse[b] * h[Eigen::Index(b)] + fluoresced[Eigen::Index(b)]
                                                      : h[Eigen::Index(b)];
            out.bands[b] = float(value * kInvPi);
        }
        return out;
    };
    glm::dvec3 lower(INFINITY), upper(-INFINITY);
    for (const glm::dvec3& x : em.vertices) {
        lower = glm::min(lower, frame.position(x));
        upper = glm::max(upper, frame.position(x));
    }
    const bool twoSided = !mesh.closed;
    for (int side = 0; side < (twoSided ? 2 : 1); ++side) {
        PackedDraw d{uint32_t(p.indices.size()), 0, int32_t(p.vertices.size()), mesh.material};
        d.closed = mesh.closed;
        d.alwaysCull = twoSided;
        d.lower = glm::vec3(lower);
        d.upper = glm::vec3(upper);
        const double flip = side == 0 ? 1.0 : -1.0;
        for (size_t v = 0; v < em.vertices.size(); ++v) {
            gpu::SpectralVertex out;
            const glm::dvec3 x = frame.position(em.vertices[v]);
            const glm::dvec3 n = flip * normals[v];
            // The back's tangent frame turned over with it: the normal map then perturbs the back
            // as the two-sided shading would mirror the front's (both tangent and its sign flip).
            const glm::dvec4 t = tangents.empty() ? glm::dvec4(0.0) : flip * tangents[v];
            const glm::dvec2 uv = uvs.empty() ? glm::dvec2(0.0) : uvs[v];
            for (int k = 0; k < 3; ++k) out.position[k] = float(x[k]);
            for (int k = 0; k < 3; ++k) out.normal[k] = float(n[k]);
            for (int k = 0; k < 2; ++k) out.uv[k] = float(uv[k]);
            for (int k = 0; k < 4; ++k) out.tangent[k] = float(t[k]);
            p.vertices.push_back(out);
            perVertex.push_back(radiance(side, v));
        }
        for (const auto& tri : em.triangles) {
            if (side == 0) p.indices.insert(p.indices.end(), {tri[0], tri[1], tri[2]});
            else p.indices.insert(p.indices.end(), {tri[0], tri[2], tri[1]});
        }
        d.indexCount = uint32_t(p.indices.size()) - d.firstIndex;
        p.draws.push_back(d);
    }
}

void layOutIndirect(PackedScene& p, const std::vector<IndirectVertex>& perVertex, int passes) {
    const size_t vertices = perVertex.size();
    p.indirect.assign(size_t(passes) * vertices * INDIRECT_RECORD_VEC4, glm::vec4(0.0f));
    for (int pass = 0; pass < passes; ++pass)
        for (size_t v = 0; v < vertices; ++v) {
            glm::vec4* dst = &p.indirect[(size_t(pass) * vertices + v) * INDIRECT_RECORD_VEC4];
            for (size_t b = 0; b < perVertex[v].bands.size(); ++b) {
                const int local = int(b) - pass * INDIRECT_VEC4 * 4;
                if (local < 0 || local >= INDIRECT_VEC4 * 4) continue;
                dst[local / 4][local % 4] = perVertex[v].bands[b];
            }
            dst[INDIRECT_SHARE] = perVertex[v].share;
        }
}

void packEmitters(PackedScene& p, const Scene& scene, const SceneOnGrid& g, const LocalFrame& frame,
                  const radiosity::SceneInterreflection& interreflection) {
    const auto& emitters = interreflection.emitters;
    static_assert(radiosity::kMaxPixelEmitters == MAX_EMITTERS && radiosity::kMaxPixelEmitterTriangles == MAX_EMITTER_TRIANGLES,
                  "the radiosity's limits are the shader's");
    if (emitters.empty()) return;
    const size_t first = scene.lights.size();
    if (first + emitters.size() > MAX_LIGHTS)
        failInput(scene.interreflection->where, "the scene's {} lights and {} emitting materials are more than the {} "
                                                "light spectra the GPU path holds",
                  first, emitters.size(), MAX_LIGHTS);
    uint32_t triangles = 0;
    for (size_t e = 0; e < emitters.size(); ++e)
        for (const auto& t : emitters[e].triangles) {
            for (int k = 0; k < 3; ++k)
                p.lights.emitterCorners[3 * triangles + uint32_t(k)] =
                    glm::vec4(glm::vec3(frame.position(t[size_t(k)])), k == 0 ? float(e) : 0.0f);
            ++triangles;
        }
    p.lights.emitters = glm::uvec4(triangles, uint32_t(emitters.size()), uint32_t(first), 0u);
    for (size_t pass = 0; pass < p.lightSpectra.size(); ++pass)
        for (size_t e = 0; e < emitters.size(); ++e)
            scatterBands(g.materials[emitters[e].material].emitted, int(pass),
                         &p.lightSpectra[pass].lightBands[(first + e) * MAX_OUTPUTS]);
}

}  // namespace metamer
