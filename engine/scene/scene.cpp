#include "scene/scene.h"

#include <algorithm>
#include <cmath>

namespace metamer {

bool Scene::hasFluorescence() const {
    for (const auto& m : materials)
        if (m.fluorescence) return true;
    return false;
}

bool Scene::hasSpecular() const {
    for (const auto& m : materials)
        if (m.hasSpecular()) return true;
    return false;
}

bool Scene::hasTransparency() const {
    for (const auto& m : materials)
        if (m.isTransparent()) return true;
    return false;
}

namespace {
// Whether every vertex of the mesh lies on its first triangle's plane and every normal is along
// it: a straight ray crosses it once, at one angle, whose normal the GPU reads from any vertex.
bool planarWithOneNormal(const Mesh& mesh) {
    if (mesh.indices.size() < 3) return false;
    const glm::dvec3 a = mesh.positions[mesh.indices[0]];
    const glm::dvec3 n = glm::cross(mesh.positions[mesh.indices[1]] - a, mesh.positions[mesh.indices[2]] - a);
    if (!(glm::length(n) > 0.0)) return false;
    const glm::dvec3 u = glm::normalize(n);
    double extent = 0.0;
    for (const glm::dvec3& p : mesh.positions) extent = std::max(extent, glm::length(p - a));
    for (const glm::dvec3& p : mesh.positions)
        if (std::abs(glm::dot(p - a, u)) > 1e-9 * extent) return false;
    for (const glm::dvec3& v : mesh.normals)
        if (!(glm::length(v) > 0.0) || std::abs(glm::dot(glm::normalize(v), u)) < 1.0 - 1e-9) return false;
    return true;
}
}  // namespace

bool Scene::transparencyInResponses() const {
    size_t channels = 0;
    const Mesh* slab = nullptr;
    for (const auto& m : materials) channels += m.isTransparent() && !m.isSlab();
    for (const Mesh& mesh : meshes) {
        if (!materials[mesh.material].isSlab()) continue;
        if (slab) return false;  // two slabs' reflections add in depth order
        slab = &mesh;
    }
    if (slab && !planarWithOneNormal(*slab)) return false;
    // One channel pass: 32 channels, or 16 in each of the two sets beside a slab.
    // A Donaldson matrix's emission needs its excitation band by band under every light.
    for (const auto& m : materials)
        if (m.fluorescence && m.fluorescence->matrix) return false;
    return channels <= (slab ? 16u : 32u) && !hasTextures();
}

bool Scene::hasEmitters() const {
    for (const auto& m : materials)
        if (m.emitter) return true;
    return false;
}

bool Scene::hasTextures() const {
    for (const auto& m : materials)
        if (m.textures.diffuse >= 0 || m.textures.specular >= 0 || (m.paint && m.paint->thicknessMap() >= 0))
            return true;
    return false;
}

bool Scene::hasNormalMaps() const {
    for (const auto& m : materials)
        if (m.textures.normal >= 0) return true;
    return false;
}

size_t Scene::triangleCount() const {
    size_t n = 0;
    for (const auto& m : meshes) n += m.indices.size() / 3;
    return n;
}

void checkMeshes(const Scene& scene) {
    Where objects{scene.file.string(), "objects", 0};
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        Where w = objects.index(m);
        if (mesh.material >= scene.materials.size())
            failInput(w, "mesh '{}' uses material {} but there are {}", mesh.name, mesh.material,
                      scene.materials.size());
        if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
            failInput(w, "mesh '{}' has {} normals for {} positions", mesh.name, mesh.normals.size(),
                      mesh.positions.size());
        if ((!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size()) ||
            (!mesh.tangents.empty() && mesh.tangents.size() != mesh.positions.size()))
            failInput(w, "mesh '{}' has {} texture coordinates and {} tangents for {} positions", mesh.name,
                      mesh.uvs.size(), mesh.tangents.size(), mesh.positions.size());
        if (mesh.indices.size() % 3 != 0)
            failInput(w, "mesh '{}' has {} indices, not a multiple of 3", mesh.name, mesh.indices.size());
        for (uint32_t i : mesh.indices)
            if (i >= mesh.positions.size())
                failInput(w, "mesh '{}' has index {} but {} positions", mesh.name, i,
                          mesh.positions.size());
    }
}

}  // namespace metamer
