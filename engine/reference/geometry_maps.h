// The ground truth that is not spectral: per pixel, which object and material the camera sees,
// how far along the ray, its shading normal, and a mask of why radiance is not reflectance ×
// illumination there. Ray cast through the reference's BVH at each pixel's central sample, for
// both backends (ReferenceRenderer::geometryMaps, reference/cpu_renderer.cpp). docs/io.md, "Ground truth".
// Tests: tests/ground_truth_test.cpp.
#pragma once

#include <cstdint>
#include <vector>

namespace metamer {

// Why a pixel's radiance is not its reflectance × illumination: bits of GeometryMaps::mask.
enum GroundTruthFlag : uint8_t {
    kTruthBackground = 1,   // no surface: every map is 0 (ids −1)
    kTruthFluorescent = 2,  // a fluorescent material: it also emits what it absorbs elsewhere
    kTruthSpecular = 4,     // the specular lobe sends more than kSpecularShare of the radiance
    kTruthTransparent = 8,  // a filter, medium or slab lies between the camera and the surface
    kTruthEmitter = 16,     // a self-luminous surface, seen from its emitting side
    // The pixel's sub-samples, or its 8 neighbours' central samples, see another surface (or the
    // background, or through other transparent objects): the maps average several surfaces, and
    // the rasterizer may have taken the other one.
    kTruthEdge = 32,
};
// The specular lobe's share of a pixel's radiance (summed over bands) above which kTruthSpecular
// is set.
inline constexpr double kSpecularShare = 0.01;

// Pixel-interleaved, row 0 at the top, at each pixel's central sample ((⌊s/2⌋ + ½)/s of the
// pixel with ssaa s: its centre for odd s).
struct GeometryMaps {
    int width = 0, height = 0;
    std::vector<int32_t> object;    // the mesh's index in the scene (Scene::meshes), −1: background
    std::vector<int32_t> material;  // the material's index (Scene::materials), −1: background
    std::vector<float> depth_m;     // distance from the camera along the ray, metres (orthographic: from the image plane); 0: background
    std::vector<float> normal;      // 3 per pixel: the shading normal in the camera frame (x right, y up, z towards the camera), 0: background
    std::vector<uint8_t> mask;      // GroundTruthFlag bits
};

}  // namespace metamer
