#include "render/shadow_maps.h"

#include "interface.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace metamer {

namespace {

// An orthonormal basis (x, y, z) with z = axis.
void basis(const glm::dvec3& axis, glm::dvec3& x, glm::dvec3& y) {
    const glm::dvec3 a = std::fabs(axis.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    x = glm::normalize(glm::cross(a, axis));
    y = glm::cross(axis, x);
}

// Rows (x, y, z) of a world → light-space rotation about `origin`, as a matrix.
glm::dmat4 view(const glm::dvec3& origin, const glm::dvec3& x, const glm::dvec3& y, const glm::dvec3& z) {
    glm::dmat4 m(1.0);
    for (int c = 0; c < 3; ++c) {
        m[c][0] = x[c];
        m[c][1] = y[c];
        m[c][2] = z[c];
    }
    m[3][0] = -glm::dot(x, origin);
    m[3][1] = -glm::dot(y, origin);
    m[3][2] = -glm::dot(z, origin);
    return m;
}

}  // namespace

ShadowMaps planShadowMaps(const Scene& scene, int size, const LocalFrame& frame) {
    ShadowMaps maps;
    maps.lights.resize(scene.lights.size());
    std::vector<glm::dvec3> points;
    for (const Mesh& mesh : scene.meshes)
        for (const glm::dvec3& p : mesh.positions) points.push_back(frame.position(p));
    if (points.empty()) return maps;
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    for (const glm::dvec3& p : points) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const double extent = std::max(glm::length(hi - lo), 1e-30);

    for (size_t l = 0; l < scene.lights.size(); ++l) {
        const Light& light = scene.lights[l];
        if (!light.castsShadows()) continue;
        const int layers = light.type == Light::Type::Point ? 6 : 1;
        if (maps.layers.size() + size_t(layers) > MAX_SHADOW_LAYERS)
            failInput(Where{scene.file.string(), light.name + ".shadows"},
                      "the shadow maps hold {} layers (one per directional light, six per point light), and this light "
                      "needs {} more; set \"shadows\": false on some lights",
                      MAX_SHADOW_LAYERS, layers);
        maps.lights[l].firstLayer = int(maps.layers.size());
        if (light.type == Light::Type::Directional) {
            // Orthographic along the light's travel, square texels, fitted to the triangles'
            // extent across the light and along it (1% margins: nothing is clipped).
            const glm::dvec3 z = glm::normalize(light.direction);
            glm::dvec3 x, y;
            basis(z, x, y);
            const glm::dvec3 c = 0.5 * (lo + hi);
            const glm::dmat4 v = view(c, x, y, z);
            glm::dvec3 a(std::numeric_limits<double>::infinity()), b(-a);
            for (const glm::dvec3& p : points) {
                const glm::dvec3 q(v * glm::dvec4(p, 1.0));
                a = glm::min(a, q);
                b = glm::max(b, q);
            }
            const double side = std::max({b.x - a.x, b.y - a.y, 1e-9 * extent}) * 1.01;
            const double depth = std::max(b.z - a.z, 1e-9 * extent), z0 = a.z - 0.01 * depth, z1 = b.z + 0.01 * depth;
            const glm::dvec2 mid(0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
            glm::dmat4 proj(1.0);
            proj[0][0] = 2.0 / side;
            proj[1][1] = 2.0 / side;
            proj[2][2] = 1.0 / (z1 - z0);
            proj[3][0] = -2.0 * mid.x / side;
            proj[3][1] = -2.0 * mid.y / side;
            proj[3][2] = -z0 / (z1 - z0);
            maps.layers.push_back({proj * v});
            maps.lights[l].texel = side / size;
        } else {
            // Six 90° views; depth (Z − n)·f/((f − n)·Z) from the near plane n to the farthest
            // corner of the bounds f.
            const glm::dvec3 lightPosition = frame.position(light.position);
            double far = 0.0;
            for (int k = 0; k < 8; ++k) {
                const glm::dvec3 corner(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
                far = std::max(far, glm::length(corner - lightPosition));
            }
            const double near = 1e-3 * extent;
            far = std::max(far * 1.01, 2.0 * near);
            const glm::dvec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
            for (const glm::dvec3& z : axes) {
                glm::dvec3 x, y;
                basis(z, x, y);
                glm::dmat4 proj(0.0);
                proj[0][0] = 1.0;
                proj[1][1] = 1.0;
                proj[2][2] = far / (far - near);
                proj[2][3] = 1.0;
                proj[3][2] = -far * near / (far - near);
                maps.layers.push_back({proj * view(lightPosition, x, y, z)});
            }
            maps.lights[l].texel = 2.0 / size;
        }
    }
    return maps;
}

}  // namespace metamer
