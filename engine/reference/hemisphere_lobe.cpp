#include "reference/hemisphere_lobe.h"

#include <numbers>

namespace metamer {

glm::dvec2 hemisphereLobe(const LobeTable* table, const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& u) {
    if (!table) return {std::numbers::pi * (1.0 + glm::dot(n, u)) / 2.0, std::numbers::pi};
    return lobeIntegrals(*table, n, v, u);
}

std::vector<bool> pairedWithPreviousHemisphere(const std::vector<Light>& lights) {
    std::vector<bool> paired(lights.size(), false);
    const Light* previous = nullptr;
    for (size_t l = 0; l < lights.size(); ++l) {
        if (lights[l].type != Light::Type::Hemisphere) continue;
        paired[l] = previous && lights[l].up == -previous->up;
        previous = &lights[l];
    }
    return paired;
}

}  // namespace metamer
