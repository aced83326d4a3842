#include "scene/scene.h"

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

bool Scene::transparencyInResponses() const {
    size_t channels = 0;
    for (const auto& m : materials) {
        if (m.isSlab()) return false;
        if (m.isTransparent()) ++channels;
    }
    return channels <= 32 && !hasTextures() && !hasFluorescence();
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
