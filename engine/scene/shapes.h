// Built-in shapes (sphere, quad, box) tessellated to world-space triangle meshes, and the mesh
// utilities the scene loader shares with the glTF reader: affine transforms and smooth normals.
#pragma once

#include "scene/scene.h"

#include <glm/glm.hpp>

#include <optional>
#include <vector>

namespace metamer {

// Limits on "segments" (docs/scene-format.md).
constexpr int kMinSphereSegments = 4;
constexpr int kMaxSphereSegments = 4096;

// A UV sphere about the y axis: `segments` meridians and segments/2 latitude bands, one vertex
// at each pole, no seam duplicates (the mesh is closed). Vertex normals are exactly (p - c)/r;
// triangles are counter-clockwise seen from outside. 2·segments·(segments/2 - 1) triangles.
// Precondition: radius > 0, segments within the limits above.
Mesh makeSphere(const glm::dvec3& center, double radius, int segments);

// The segments a sphere gets when the scene does not say: edges of about 6 pixels along its
// silhouette as `camera` sees it (a silhouette within 0.1 px of the true circle for spheres over
// 45 px in radius), a multiple of 8 in 16 … 512. A sphere that holds the camera gets 512.
// Rasterizing costs lavapipe about as much per triangle as shading a few pixels, so a mesh
// finer than the pixels it covers is paid for and not seen (docs/performance.md).
int sphereSegmentsFor(const Camera& camera, const glm::dvec3& center, double radius);

// Whether `mesh` is closed and wound outwards (Mesh::closed), its vertices welded by exact
// position (a seam's duplicates join); spheres are by construction.
bool isClosedOutward(const Mesh& mesh);

// A w×h rectangle centred at `center` facing `normal`. In-plane axes: "up" is the hint (default
// +y, or -z when the normal is within ~2.6° of ±y and no hint was given) made perpendicular to
// the normal; "right" = up × normal. The size is (right extent, up extent). Two triangles,
// counter-clockwise seen from the normal side. Precondition: normal ≠ 0, hint not parallel to it.
Mesh makeQuad(const glm::dvec3& center, const glm::dvec3& normal, const glm::dvec2& size,
              const std::optional<glm::dvec3>& upHint = std::nullopt);

// An axis-aligned box centred at `center` with edge lengths `size` (x, y, z): six faces of two
// triangles, each face's four corners with the face's normal (flat shading), counter-clockwise
// seen from outside; closed once welded by position (isClosedOutward). Precondition: size > 0.
Mesh makeBox(const glm::dvec3& center, const glm::dvec3& size);

// The in-plane axes makeQuad uses; nullopt when the hint is (nearly) parallel to the normal.
struct QuadAxes {
    glm::dvec3 right, up, normal;
};
std::optional<QuadAxes> quadAxes(const glm::dvec3& normal, const std::optional<glm::dvec3>& upHint);

// M = T · Rz · Ry · Rx · S: scale first, then rotate about x, then y, then z (degrees), then
// translate.
glm::dmat4 objectTransform(const glm::dvec3& translate, const glm::dvec3& rotateDeg,
                           const glm::dvec3& scale);

// Positions by m, normals by the inverse-transpose of its 3×3 part (renormalized). A mirroring
// transform (det < 0) reverses each triangle's index order so the winding stays
// counter-clockwise seen from the normal side. Precondition: m is invertible.
void transformMesh(Mesh& mesh, const glm::dmat4& m);

// Per-vertex tangents from texture coordinates (when a glTF file has none): the area-weighted
// ∂p/∂u of the triangles around each vertex, made perpendicular to its normal; w = ±1 so that
// cross(n, t)·w points towards decreasing v (up the image), the handedness glTF uses. A vertex
// whose triangles have no UV area gets (0, 0, 0, 0): no normal mapping there. (Not MikkTSpace:
// a normal map baked against MikkTSpace tangents shows small differences on curved meshes.)
std::vector<glm::dvec4> tangentsFromUvs(const std::vector<glm::dvec3>& positions, const std::vector<glm::dvec3>& normals,
                                        const std::vector<glm::dvec2>& uvs, const std::vector<uint32_t>& indices);

// Area-weighted smooth vertex normals: each vertex gets the normalized sum of the (unnormalized)
// cross products of the triangles that use it. A vertex no triangle with area uses gets +z.
std::vector<glm::dvec3> smoothNormals(const std::vector<glm::dvec3>& positions,
                                      const std::vector<uint32_t>& indices);

}  // namespace metamer
