// The CPU reference renderer: ray casting in double precision, one ray per sub-sample, local
// illumination (one scattering event; with the scene's interreflection key, the indirect light of
// reference/indirect_light.h added), with exact shadow rays through the BVH
// for directional and point lights. Rays pass straight through transparent objects (filters and
// absorbing media), which multiply what is behind them band by band; so do shadow rays (coloured
// shadows), and fluorescence is excited by the filtered light. It shares only the Scene model and the
// SceneOnGrid spectra with the GPU path and produces the goldens the GPU is checked against.
// Every convention (camera, pixels, shading) is spelled out in docs/physics.md.
#pragma once

#include "reference/lobe_table.h"

#include "reference/bvh.h"
#include "reference/geometry_maps.h"
#include "reference/indirect_light.h"
#include "scene/scene.h"
#include "scene/scene_on_grid.h"
#include "scene/surface_quantity.h"
#include "spectral/cube.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace metamer {

struct ReferenceOptions {
    int ssaa = 1;     // s×s sub-samples per pixel on a regular grid, box-averaged
    int threads = 0;  // 0 = usableCpuCount() (core/cpu_count.h)
    // What the cube holds: the radiance, or a ground-truth map (scene/surface_quantity.h).
    SurfaceQuantity quantity = SurfaceQuantity::Radiance;
    // False: the scene's interreflection is not solved (no indirect light), for a renderer that
    // only casts the geometry maps (render/ground_truth.cpp on the GPU backend).
    bool interreflection = true;
    // Rows finished so far of all rows, on the calling thread, at most about 4 times a second;
    // it may throw to stop the render (the exception comes out of render()). Empty: none.
    std::function<void(int rowsDone, int rows)> progress;
};

// objectId values besides a mesh index.
inline constexpr int32_t kBackgroundId = -1;
inline constexpr int32_t kMixedId = -2;  // the pixel's sub-samples saw different meshes (or sky)

// Which shadowing lights reach a sample: bit (k mod 64) for the k-th light that casts shadows
// (Light::castsShadows), set when it is blocked. kMixedShadows: the pixel's sub-samples differ.
inline constexpr uint64_t kMixedShadows = ~uint64_t(0);

// Which transparent surfaces a sample's ray crossed before its opaque hit, and which its shadow
// rays crossed (coloured shadows), as a signature (0: none; the same set of crossings, the same
// value). kMixedCrossings: the pixel's sub-samples differ.
inline constexpr uint32_t kMixedCrossings = ~uint32_t(0);

struct ReferenceImage {
    SpectralCube cube;             // spectral radiance per band, W·sr⁻¹·m⁻²·nm⁻¹
    std::vector<int32_t> objectId;  // per pixel, row 0 at the top: mesh index, -1 or -2
    std::vector<uint64_t> shadows;  // per pixel: the blocked shadowing lights, or kMixedShadows
    // Per pixel: the transparent crossings' signature, or kMixedCrossings. Where it changes is a
    // transparent object's silhouette, an edge as much as an opaque object's (render_job's edgeMask).
    std::vector<uint32_t> crossings;
};

ReferenceImage renderReference(const Scene& scene, const SceneOnGrid& onGrid,
                               const ReferenceOptions& options = {});

// The renderer behind renderReference, exposed so tests can check pixels in double before they
// are rounded to float in the cube. Holds references: scene and onGrid must outlive it.
class ReferenceRenderer {
public:
    ReferenceRenderer(const Scene& scene, const SceneOnGrid& onGrid,
                      const ReferenceOptions& options = {});

    int bands() const { return bands_; }
    // Where rays and hit points live: positions in this frame's units (scene/local_frame.h).
    const LocalFrame& frame() const { return frame_; }

    // The primary ray through image position (px, py) in pixels (x right, y down, (0,0) the
    // image's top-left corner), in frame().
    Ray cameraRay(double px, double py) const;

    // Radiance along one ray into `radiance` (bands() values, overwritten); returns the mesh
    // index hit, or kBackgroundId.
    // `blocked`, when given, gets the shadowing lights the hit point does not see (see kMixedShadows).
    // `crossings`, when given, gets the signature of the transparent surfaces crossed (kMixedCrossings).
    int32_t trace(const Ray& ray, double* radiance, uint64_t* blocked = nullptr, uint32_t* crossings = nullptr) const;

    // Box-averaged radiance of pixel (x, y) over the ssaa×ssaa sub-samples; returns its objectId.
    int32_t pixel(int x, int y, double* radiance, uint64_t* blocked = nullptr, uint32_t* crossings = nullptr) const;

    ReferenceImage render() const;
    // What render() computes from now on (options.quantity): one renderer, and one solve of the
    // interreflection, for the radiance and every ground-truth map.
    void setQuantity(SurfaceQuantity quantity) { options_.quantity = quantity; }

    // Object and material ids, depth, normal and the ground-truth mask at every pixel's central
    // sample (reference/geometry_maps.h); the specular share is the radiance's, whatever
    // options.quantity says, and of the direct light only (the mask's test needs no indirect
    // light: a lobe's share of the direct light is at least its share of all).
    GeometryMaps geometryMaps() const;

private:
    // A ray's hit as the shading sees it: the point, the face normal, the shading normal (vertex
    // normals interpolated, the normal map applied, turned towards the eye), the texture coordinates.
    struct SurfacePoint {
        uint32_t mesh = 0, material = 0;
        glm::dvec3 p{0.0}, ng{0.0}, n{0.0};
        glm::dvec2 uv{0.0};
    };
    SurfacePoint surfacePoint(const RayHit& hit, const Ray& ray) const;
    // The ground-truth mask's specular test at one sample (geometryMaps).
    bool specularDominates(const RayHit& hit, const Ray& ray) const;
    // Outgoing radiance at a hit, towards -ray.direction (or options.quantity's map). `crossed`
    // gets the signature of the transparent objects its lights came through (coloured shadows),
    // added to; `specular`, when given (bands() values), the specular lobe's part, added to, and
    // then the radiance is the direct light's alone (no indirect light).
    void shade(const RayHit& hit, const Ray& ray, double* radiance, uint64_t& blocked, uint32_t& crossed,
               double* specular = nullptr) const;
    // Whether light l is blocked between p (on triangle `triangle`) and the light, along w.
    bool inShadow(size_t l, const glm::dvec3& p, const glm::dvec3& w, uint32_t triangle) const;
    // Multiplies `radiance` by the transmittance of the transparent surfaces and media the ray
    // crosses before t = tEnd (the opaque surface it ends on).
    // Returns the crossings' signature (ReferenceImage::crossings).
    uint32_t transmit(const Ray& ray, double tEnd, double* radiance) const;
    // The transparent crossings of `ray` in (tMin, tEnd): `factor` gets the transmittance per band,
    // or is left empty when there are none; returns their signature.
    // `reflected`, when given (bands() values), gets the slabs' reflections added, each times the
    // transmittance in front of it.
    uint32_t crossings(const Ray& ray, double tMin, double tEnd, std::vector<double>& factor,
                       double* reflected = nullptr) const;
    // The radiance a mirror sees in unit direction r, band b: hemisphere lights and ambient light.
    double environment(const glm::dvec3& r, int b) const;
    // Light l's transmittance to p along w (a coloured shadow) into `factor`; false when nothing
    // transparent lies on the way.
    // `signature` gets the crossings' (ReferenceImage::crossings), 0 for none.
    bool lightTransmittance(size_t l, const glm::dvec3& p, const glm::dvec3& w, std::vector<double>& factor,
                            uint32_t& signature) const;
    // The material's fluorescence per unit geometric factor under light l filtered by tau (per band).
    void filteredFluorescence(uint32_t material, size_t l, const double* tau, double* out) const;
    // What the direct light makes the surface at p send diffusely (normal n, on BVH triangle
    // `triangle`, texture coordinates uv): π × its diffuse and fluorescent radiance, per band — the
    // E of the interreflection (reference/indirect_light.h).
    void directRadiosity(uint32_t triangle, const glm::dvec3& p, const glm::dvec3& n, const glm::dvec2& uv,
                         double* out) const;
    // The indirect light's radiance at a shaded point, added to `radiance`: ρd·H/π and the
    // fluorescence H excites.
    void addIndirect(uint32_t material, uint32_t triangle, const glm::dvec3& p, const glm::dvec3& n,
                     const double* diffuseTexture, double* radiance) const;

    const Scene& scene_;
    const SceneOnGrid& onGrid_;
    ReferenceOptions options_;
    int bands_ = 0;
    LocalFrame frame_;  // positions below are in its units: the camera's, the lights', the BVH's
    Camera camera_;
    Bvh bvh_;       // the opaque triangles: primary hits and shadow rays
    Bvh clearBvh_;  // the transparent ones (filters and media), crossed on the way to an opaque hit
    std::vector<glm::dvec3> lightPositions_;  // per light, in the frame (point lights')

    // Camera basis and projection scale (docs/physics.md, "Camera").
    glm::dvec3 f_, r_, u_;
    double aspect_ = 1.0;
    double tanHalf_ = 0.0;     // perspective
    double halfHeight_ = 0.0;  // orthographic, frame units

    // View-independent spectra per (material, light), flattened [material][light][band]:
    // diffuse ρd·E/π; specular ρs·E·(N+8)/(8π); fluorescence (Φ/π)·ê(λ)/λ·S with
    // S = Σ a·E·λ·Δλ, or for a Donaldson matrix (1/π)·Σᵢ D(λi, λ)·E(λi)·Δλ. Each is scaled per hit
    // by its geometric factor.
    std::vector<double> diffuseTerm_, specularTerm_, fluorescenceTerm_;
    std::vector<bool> hasSpecular_, hasFluorescence_;  // per material
    std::vector<int> shadowBit_;                       // per light: its bit in `blocked`, or -1
    std::vector<bool> pairedHemisphere_;               // per light: pairedWithPreviousHemisphere
    std::vector<std::shared_ptr<const LobeTable>> lobeTables_;  // per material: its lobe table, or null
    double sceneScale_ = 1.0;                          // the largest coordinate's magnitude, frame units
    std::unique_ptr<IndirectLight> indirect_;          // with the scene's interreflection
    size_t termOffset(uint32_t material, size_t light) const {
        return (static_cast<size_t>(material) * onGrid_.lights.size() + light) * bands_;
    }
};

}  // namespace metamer
