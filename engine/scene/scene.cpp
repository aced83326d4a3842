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

bool Scene::hasTextures() const {
    for (const auto& m : materials)
        if (m.textures.diffuse >= 0 || m.textures.specular >= 0) return true;
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

}  // namespace metamer
