// What interreflection computes from the geometry alone — the elements' form factors and the
// vertices' gather factors — kept for the process, keyed by their inputs' content (the elements'
// corners, the points, the occluders' triangles), so that a sweep over light or material spectra
// (a batch, the Python module, the preview's spectrum swaps) pays the solve and not the geometry.
// The key is a hash of the inputs checked against a copy of them: a hit is the same inputs, not a
// likely one. The most recent kGeometryCacheEntries of each kind are kept (the form factors take
// elements² × 8 bytes), and the last solution on the most recent form factors.
// Tests: engine/radiosity/scene_radiosity_test.cpp (a spectrum change).
#pragma once

#include "radiosity/element_coupling.h"
#include "radiosity/solver.h"
#include "radiosity/vertex_gather.h"

#include <memory>
#include <optional>

namespace metamer::radiosity {

inline constexpr size_t kGeometryCacheEntries = 2;

// formFactorMatrix(elements, &occluders, source), or the same inputs' result kept from before
// (`hit` says which; its `seconds` are the computation's, when it was made).
std::shared_ptr<const Coupling> cachedFormFactors(std::span<const std::array<glm::dvec3, 3>> elements, const Bvh& occluders,
                                                  std::span<const uint32_t> source, bool& hit);

// gatherFactors(points, elements, &occluders, side), or the same inputs' result kept from before.
std::shared_ptr<const Eigen::MatrixXd> cachedGatherFactors(std::span<const GatherPoint> points,
                                                           std::span<const std::array<glm::dvec3, 3>> elements,
                                                           const Bvh& occluders, int side, bool& hit);

// The last solve on a set of form factors (one is kept): what it was given and what it found, so
// that the next solve on them — a sweep's next spectrum — is it rescaled (solver.h,
// rescaledSolution) or starts from it (`start`).
struct LastSolve {
    Problem problem;  // without its form factors (the Coupling holds them)
    Solution solution;
};
std::optional<LastSolve> lastSolveOn(const Coupling& factors);
void keepLastSolve(const std::shared_ptr<const Coupling>& factors, LastSolve solve);

// Forgets everything kept (tests; the memory).
void clearGeometryCache();

}  // namespace metamer::radiosity
