#include "reference/geometry_maps.h"

#include "core/parallel_for.h"
#include "reference/cpu_renderer.h"

#include <numeric>

namespace metamer {

namespace {
constexpr double kRayTMin = 1e-9;  // as cpu_renderer.cpp's: frame units along a unit direction
}

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
            g.mask[at] = mask | kTruthBackground;
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
        g.mask[at] |= mask;
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
