// The spectral pass's packing: everything the fragment shader reads, laid out per pass for the
// uniform blocks of shaders/interface.h, and the vertex and index arrays — plain C++, computed
// once per scene in double and rounded once to float, with no Vulkan object. The pass
// (render/spectral_pass) uploads it. Tests: render/spectral_packing_test.cpp.
#pragma once

#include "interface.h"
#include "radiosity/scene_radiosity.h"
#include "render/shadow_maps.h"
#include "scene/local_frame.h"
#include "scene/scene.h"
#include "scene/scene_on_grid.h"

#include <array>
#include <cstdint>
#include <vector>

namespace metamer {

// One draw call: a mesh's indices, with its material; whether the mesh is closed (Mesh::closed)
// and its bounds in the frame's units (back faces may be culled when the camera is outside them).
struct PackedDraw {
    uint32_t firstIndex, indexCount;
    int32_t vertexOffset;
    uint32_t material;
    bool closed = false;
    bool transparent = false;  // a filter or medium: drawn by the transmission pass only
    bool alwaysCull = false;   // one side of an interreflected open mesh: its back faces are culled always
    glm::vec3 lower{0.0f}, upper{0.0f};
};

// Everything the fragment shader reads, packed per pass for the uniform blocks of interface.h.
struct PackedScene {
    std::vector<gpu::SpectralVertex> vertices;
    std::vector<uint32_t> indices;
    std::vector<PackedDraw> draws;
    // Interreflection (render/indirect_packing.h): the indirect light per pass and vertex,
    // [pass][vertex][INDIRECT_VEC4], drawn by the INDIRECT programs; empty without.
    std::vector<glm::vec4> indirect;
    int ambient = 0, directional = 0, point = 0, hemisphere = 0;  // light counts, in this order in every block
    // The first shadowedDirectional directional and shadowedPoint point lights cast shadows; bit i
    // of hemispherePaired: hemisphere light i's up is exactly opposite light i − 1's (interface.h).
    int shadowedDirectional = 0, shadowedPoint = 0;
    uint32_t hemispherePaired = 0;
    gpu::GpuLightBlock lights{};
    // The shadow maps' layers (render/shadow_maps.h) and their matrices for the shader.
    ShadowMaps shadowMaps;
    gpu::GpuShadowBlock shadowBlock{};
    // Per shadow-map layer, where its light is, for the coloured shadows' passes drawn from it:
    // xyz the point light's position in the frame (w = 1), or the directional light's direction of
    // travel (w = 0).
    std::vector<glm::vec4> shadowEyes;
    std::vector<gpu::GpuLightSpectraBlock> lightSpectra;  // per pass
    std::vector<gpu::GpuMaterialBlock> materials;         // per pass × material: [pass][material]
    // Coloured shadows (scenes with transparent objects and shadowing lights; interface.h,
    // SPEC_FILTERED_SHADOWS): bandLayers = ⌈bands/4⌉, and per fluorescent material, per light,
    // what its emission under a filtered light is summed from — the rank-one form's excitation
    // integrand (Φ/π)·a·E·λ·Δλ·2ˢ (bandLayers vec4: the coupling's terms), or in a scene with a
    // Donaldson matrix the matrix (1/π)·D·E·Δλ (4·bandLayers rows of input bands × bandLayers vec4
    // of output bands). A material's params.z is its first entry; one zero entry when none.
    bool filteredShadows = false;
    int bandLayers = 0;
    std::vector<glm::vec4> shadowExcitation;
    // The optical-depth channels (interface.h; coloured shadows, the camera's channel pass):
    // depthChannels sheets' and media's, then slabChannels slabs' pairs; depthLayers =
    // ⌈(depthChannels + 2·slabChannels) / 4⌉ map layers per shadow-map layer; depthSpectra: per channel, bandLayers vec4 (BINDING_DEPTH_SPECTRA; one
    // zero entry when none). A transparent material's first channel is its params.w.
    int depthChannels = 0, slabChannels = 0, depthLayers = 0;
    std::vector<glm::vec4> depthSpectra;
    // Flat slabs (bit i: slab i's objects all have parallel normals, i < 32) under directional
    // lights: log2 T at that light's one angle, [shadow-map layer][slab][band layer] from entry
    // slabLayerRows of depthSpectra (rows of point lights' layers unused, 0).
    uint32_t flatSlabs = 0;
    int slabLayerRows = 0;
    // With hemisphere lights: the lobe table of every distinct gloss value of the specular
    // materials (reference/lobe_table.h), one after another; a material's lobe.x is its first entry.
    std::vector<glm::uvec4> lobeTables;
    // Fluorescence as per-light spectra (scenes with a Donaldson matrix; interface.h,
    // GpuFluorescenceBlock): records of lightSlots × MAX_OUTPUTS vec4; per pass, record 0 is zeros
    // (non-fluorescent materials, and the only record when fluorescenceSpectra is false) and record
    // 1 + j the j-th fluorescent material's. [pass][record][light][k].
    bool fluorescenceSpectra = false;
    int lightSlots = 1;  // max(1, light count)
    int fluorescenceRecords = 1;                  // per pass
    std::vector<uint32_t> fluorescenceRecord;     // per material: its record in every pass
    std::vector<glm::vec4> fluorescence;

    // The response pass (pack() with detector weights): per material, its responses under every
    // light, and the textures it reads instead of its spectral ones — a reflectance texture
    // becomes a response texture (RESPONSE_VEC4 layers per light, texel by texel), a normal map
    // stays as it is. responseTextureSlots[m]: diffuse, specular, normal texture in responseTextures.
    bool responses = false;
    int responseChannels = 0;
    // The band layers [first, end) where any detector weight is nonzero (SPEC_RESPONSE_FIRST_LAYER).
    int responseFirstLayer = 0, responseEndLayer = 0;
    // Single-crossing tables (render/crossing_tables.h): their header's first row in depthSpectra
    // (−1: none) and every channel's nodes together (SPEC_CROSSING_HEADER, SPEC_CROSSING_NODES).
    int crossingHeader = -1, crossingNodes = 0;
    size_t crossingTexels = 0;  // the tables' RGBA32F texels (header included)
    std::vector<gpu::GpuResponseBlock> responseBlocks;
    std::vector<TextureOnGrid> responseTextures;
    std::vector<std::array<int, 3>> responseTextureSlots;
};

// The material's MATERIAL_* bits (interface.h); `specular`: whether its lobe is drawn.
uint32_t materialSwitches(const MaterialOnGrid& m, bool specular);

// Band b of pass p lives at vec4 k = (b - 32p) / 4, component (b - 32p) % 4; bands past the grid are 0.
void scatterBands(const std::vector<double>& values, int pass, glm::vec4* dst);

// The scene packed for `passes` passes of BANDS_PER_PASS bands, its positions in `frame`
// (scene/local_frame.h); with `interreflection`, its opaque meshes as their elements and their
// indirect light (render/indirect_packing.h). Input errors (lights or fluorescence beyond
// float32's range) name the scene's key.
PackedScene pack(const Scene& scene, const SceneOnGrid& g, int passes, const LocalFrame& frame,
                 const radiosity::SceneInterreflection* interreflection = nullptr);

// Interreflection as the spectral pass draws it (render/indirect_packing.cpp; docs/physics.md,
// "Interreflection"): each opaque mesh replaced by its elements (radiosity/scene_radiosity.h) —
// their vertices with the mesh's normals, texture coordinates and tangents interpolated — and an
// open mesh's two sides as two copies, each drawn with its back faces culled (the back copy wound
// the other way, its normals and tangent frame turned over), so that every fragment shows the side
// whose indirect light it has; and per vertex and pass the INDIRECT_VEC4 vec4 of that light
// (shaders/interface.h, VERTEX_INDIRECT): H/π, or for a fluorescent surface (ρd·H + M·H)/π, and
// the emitters' shares D/U (their direct light drawn per pixel; on a fluorescent surface 0, its H
// then holding their direct light too).
// packIndirectMesh appends mesh m's elements to p's vertices, indices and draws, and their light to
// `perVertex` [emitted vertex]; layOutIndirect makes p.indirect from it, [pass][vertex][record].
struct IndirectVertex {
    std::vector<float> bands;  // every band of the grid
    glm::vec4 share{0.0f};     // per emitter
};
void packIndirectMesh(PackedScene& p, std::vector<IndirectVertex>& perVertex, const Scene& scene, const SceneOnGrid& g,
                      const LocalFrame& frame, size_t m, const radiosity::SceneInterreflection& interreflection);
void layOutIndirect(PackedScene& p, const std::vector<IndirectVertex>& perVertex, int passes);
// The emitters drawn per pixel into p.lights (their triangles) and p.lightSpectra (their radiance,
// after the scene's lights); p.lightSpectra must be laid out.
void packEmitters(PackedScene& p, const Scene& scene, const SceneOnGrid& g, const LocalFrame& frame,
                  const radiosity::SceneInterreflection& interreflection);

// Per sheet and medium channel, twice the deepest one straight path can cross (the camera's and a
// light's added; render/crossing_tables.h): a sheet material's triangle count, a medium's
// bounding-box diagonal (a straight line inside a box is at most its diagonal long); 0: not drawn.
std::vector<double> crossingDepthBounds(const PackedScene& p, const SceneOnGrid& g);

// The scene packed for the response pass: one pass whose outputs are the channels of a detector
// with `weights` [channel][band of g.grid] (at most 4·RESPONSE_VEC4 channels): every material's
// responses under every light, in double, rounded once to float.
// Through sheets and media it adds single-crossing tables (render/crossing_tables.h) where every
// row fits in `texelLimit` (the device's maxTexelBufferElements); without them the pass sums per band.
PackedScene packResponses(const Scene& scene, const SceneOnGrid& g, const std::vector<std::vector<double>>& weights,
                          const LocalFrame& frame, uint64_t texelLimit = UINT64_MAX);

}  // namespace metamer
