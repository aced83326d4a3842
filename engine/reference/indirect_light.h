// The CPU reference's interreflection (docs/physics.md, "Interreflection"), computed its own way —
// not radiosity/'s, which the GPU path draws, so that each checks the other:
//   patches: every opaque triangle cut uniformly into k × k, both sides of an open mesh, the
//     outside of a closed one; each patch's direct radiosity E from the renderer's own light loop,
//     the mean over the patch cut again into 6 × 6; its reflectance ρd (times its texture at its
//     centroid);
//   form factors by casting rays: from each patch's centroid a deterministic cosine-weighted set of
//     directions (S × S strata), F_ij the share that first hits patch j's side — in a closed scene
//     every ray hits something, so every row sums to exactly 1;
//     the bright patches (every self-luminous patch's front where they cover less than half the
//     surfaces, then those sending 8 × the area-weighted mean or more, at most 512: an emitting
//     wall at a floor's edge, a light's hot spot on a nearby surface, too small for the strata to
//     find evenly) by integrating cos θ·cos θ'/(π r²) over their area instead;
//   the radiosity by Gauss–Seidel sweeps, band after band in order of wavelength, the fluorescent
//     re-emission of the bands before as a source, until no patch changes by more than 10⁻¹⁰ of
//     the largest;
//   at a shaded point, a final gather: H = the mean radiosity of the patches a cosine-weighted set
//     of rays from it first hits (π × the mean incoming radiance), the bright ones by area.
// Everything in double, in the renderer's frame. Tests: tests/interreflection_test.cpp (furnaces on
// both renderers, the GPU against this).
#pragma once

#include "reference/bvh.h"
#include "scene/scene.h"
#include "scene/scene_on_grid.h"

#include <array>
#include <functional>
#include <vector>

namespace metamer {

class IndirectLight {
public:
    // What the direct light makes a surface send at p (normal n, on BVH triangle `triangle`, texture
    // coordinates uv): its diffuse radiosity per band, W·m⁻²·nm⁻¹ (ρd·E plus its fluorescence).
    using DirectRadiosity =
        std::function<void(uint32_t triangle, const glm::dvec3& p, const glm::dvec3& n, const glm::dvec2& uv, double* out)>;

    // `patchSize` in the frame's units (no patch edge longer); `strata`: S of the S × S directions
    // of every form-factor row and final gather.
    IndirectLight(const Scene& scene, const SceneOnGrid& spectra, const Bvh& opaque, const DirectRadiosity& direct,
                  double patchSize, int strata);

    // The irradiance H at p, on the side of unit normal n, leaving BVH triangle `skip`, into
    // H[bands]: W·m⁻²·nm⁻¹.
    void irradiance(const glm::dvec3& p, const glm::dvec3& n, uint32_t skip, double* H) const;

    size_t patches() const { return centroid_.size(); }
    int sweeps() const { return sweeps_; }

private:
    // The patch a ray hit, on the side it arrived at, or −1 (the inside of a closed mesh, nothing).
    long patchHit(const Ray& ray, uint32_t skip) const;
    // The factor from the point x (normal n, on BVH triangle skip) to patch j, integrated over j's area.
    double areaFactor(const glm::dvec3& x, const glm::dvec3& n, uint32_t skip, uint32_t j) const;

    const Scene& scene_;
    const SceneOnGrid& g_;
    const Bvh& bvh_;
    int bands_ = 0, strata_ = 0;
    std::vector<uint32_t> firstPatch_, cuts_;  // per BVH triangle: its first patch (front side), k
    std::vector<bool> twoSided_;                // per BVH triangle: whether its back has patches (k² after the front's)
    std::vector<glm::dvec3> centroid_, normal_;  // per patch (side)
    std::vector<std::array<glm::dvec3, 3>> corners_;
    std::vector<double> area_;
    std::vector<bool> bright_;            // per patch: gathered from by area (brightList_), not by the strata
    std::vector<uint32_t> brightList_;
    std::vector<uint32_t> triangle_;            // per patch: its BVH triangle
    std::vector<double> radiosity_;             // per patch × band: B
    int sweeps_ = 0;
};

}  // namespace metamer
