// Diffuse interreflection of a scene, computed once on its grid (docs/physics.md,
// "Interreflection"): its opaque meshes cut into elements (radiosity/element_mesh.h), their form
// factors with occlusion (element_coupling.h), what the direct light makes each element send —
// every light kind, shadows included, and the fluorescence it excites (the E of solver.h) — the
// radiosity solved in every band with the surfaces' re-emission (solver.h), and the indirect
// irradiance H at every element vertex (vertex_gather.h), which the renderer interpolates across
// each element and multiplies by the surface's own reflectance at the pixel (textures included).
// Then, up to `refine` times, the element edges along which H changes by more than
// refine_threshold × the mean vertex H are bisected (radiosity/element_mesh.h, refineEdges: no
// T-junctions) and everything is solved again: elements gather at contacts and shadow edges.
//
// Each side of an open mesh is its own surface (two-sided shading: a quad lit from behind shows
// its back); a closed mesh has its outside only. What is not interreflected: the specular lobe
// (a glossy surface reflects the indirect light diffusely only, by its ρd), and light through
// transparent objects (a scene with both is refused when it is read).
// Tests: engine/radiosity/scene_radiosity_test.cpp (a closed room of uniform reflectance under
// ambient light: the indirect irradiance is ρE/(1 − ρ) everywhere; two facing walls).
#pragma once

#include "radiosity/element_mesh.h"
#include "radiosity/element_coupling.h"
#include "radiosity/solver.h"
#include "scene/scene.h"
#include "scene/scene_on_grid.h"

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace metamer::radiosity {

struct MeshInterreflection {
    ElementMesh elements;  // the mesh refined
    // [element vertex][band]: the indirect irradiance H, W·m⁻²·nm⁻¹, on the side the mesh's normal
    // points to, and on its back (empty for a closed mesh). Zero-sized for a mesh left out (transparent).
    // With SceneInterreflection::emitters, H leaves out what the emitters send directly.
    Eigen::MatrixXd front, back;
    // [element vertex][emitter], per side, with SceneInterreflection::emitters: D, the irradiance a
    // unit radiosity on the emitter's front makes there past the occluders (Σ of the gather factors
    // over its elements), and U, the same unoccluded (the closed form over its triangles). The
    // emitter's direct irradiance is πL_e·D; the renderer draws it per pixel as πL_e·(D/U)·U(pixel).
    Eigen::MatrixXd frontDirect, backDirect, frontUnoccluded, backUnoccluded;
    // [element vertex][emitter]: the share D/U the renderer interpolates (where U = 0, the mean of
    // the neighbours' that the emitter reaches).
    Eigen::MatrixXd frontShare, backShare;
};

// A self-luminous material whose direct light the renderer draws per pixel: its front triangles
// (the input meshes', not the elements), metres, counter-clockwise seen from the front.
struct EmitterGeometry {
    uint32_t material = 0;
    std::vector<std::array<glm::dvec3, 3>> triangles;
};
// Up to this many emitting materials with this many triangles in all are drawn per pixel; a scene
// with more takes their direct light from the vertices too, as the rest of H (interface.h).
constexpr size_t kMaxPixelEmitters = 4, kMaxPixelEmitterTriangles = 64;

struct SceneInterreflection {
    std::vector<MeshInterreflection> meshes;  // [Scene::meshes index]
    std::vector<EmitterGeometry> emitters;    // drawn per pixel (empty: none, or too many)
    size_t elements = 0;                      // surfaces' elements solved (both sides of open meshes)
    std::vector<double> area;                 // theirs, m² (in the order of solution.radiosity's rows)
    Coupling coupling;                        // the form factors (the last pass's) and what they cost
    Solution solution;
    std::vector<size_t> refinement;           // elements each refinement pass added
    bool refinementStopped = false;           // a pass reached max_elements
    bool formFactorsKept = false;             // the last pass's form factors came from the geometry cache (geometry_cache.h)
    double tolerance = 0.0;                   // the solve's, asked (Interreflection::tolerance)
    bool warmStart = false;                   // its solve started from the last solve on them (scaled per band)
    double formFactorSeconds = 0.0, gatherSeconds = 0.0, totalSeconds = 0.0;  // over all passes
    std::string describe() const;  // one line for -v: elements, the bound, the times
};

// A fluorescent material's re-emission on the grid, M(out, in): the radiosity it sends in band
// `out` per irradiance in band `in` (π × the renderers' fluorescence radiance: Φ·ê(out)/λout·a(in)·λin·Δλ
// for an excitation/emission pair, D(in, out)·Δλ for a Donaldson matrix); empty for another.
Eigen::MatrixXd reemissionMatrix(const MaterialOnGrid& material, const SceneOnGrid& spectra);

// The element size the scene asks for, or its default: the opaque objects' bounding-box diagonal
// over 24 (metres).
double elementSize(const Scene& scene);

// `scene.interreflection` must be set (its settings are used).
SceneInterreflection solveInterreflection(const Scene& scene, const SceneOnGrid& spectra);

}  // namespace metamer::radiosity
