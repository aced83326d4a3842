// The one place that defines the spectral pass's interface: descriptor bindings, specialization
// constant ids, push constants and uniform-block records. Included by C++ (engine/render) and by
// GLSL (shaders/*.vert, *.frag), so neither restates a binding number or a struct layout.
//
// Why uniform blocks, laid out per pass: every spectral value a fragment reads sits at an offset
// known when the shader is compiled (band k of this pass, light l), so the loads are uniform
// across a SIMD batch of fragments. lavapipe turns such loads into one scalar load and a
// broadcast; a storage buffer indexed at run time costs a gather per fragment (60× slower here).
#ifndef METAMER_SHADERS_INTERFACE_H
#define METAMER_SHADERS_INTERFACE_H

#ifdef __cplusplus
#include <glm/glm.hpp>
#include <cstdint>
namespace metamer::gpu {
using uint = uint32_t;
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using ivec4 = glm::ivec4;
using mat4 = glm::mat4;
#endif

// Colour attachments per pass (lavapipe's maxColorAttachments), 4 bands each: 32 bands a pass.
// spectral.frag is built once per attachment count 1..MAX_OUTPUTS (define OUTPUT_COUNT).
#define MAX_OUTPUTS 8
#define BANDS_PER_PASS (4 * MAX_OUTPUTS)
// Lights per scene: the per-pass light spectra block is MAX_LIGHTS × MAX_OUTPUTS vec4 = 16 KiB,
// the smallest maxUniformBufferRange Vulkan guarantees.
#define MAX_LIGHTS 128

// Descriptor set 0 of the spectral pass.
#define BINDING_LIGHTS 0          // GpuLightBlock (static)
#define BINDING_LIGHT_SPECTRA 1   // GpuLightSpectraBlock, dynamic offset: this pass's bands
#define BINDING_MATERIAL 2        // GpuMaterialBlock, dynamic offset: this pass's bands of this material
#define BINDING_FLUORESCENCE 3    // GpuFluorescenceBlock, dynamic offset: this pass's bands of this material's
                                  // fluorescence under every light (read when SPEC_FLUORESCENCE_SPECTRA)
#define BINDING_RESPONSES 4       // GpuResponseBlock, dynamic offset: this material's detector responses
                                  // under every light (read when SPEC_RESPONSES)
#define BINDING_SHADOW_MATRICES 5 // GpuShadowBlock (static): world → clip of every shadow-map layer
#define BINDING_SHADOW_MAP 6      // sampler2DArrayShadow: the shadow maps, one layer per directional light,
                                  // six per point light (read when SPEC_SHADOWS)
#define BINDING_LOBE_WEIGHTS 7    // sampler2D (RGBA32F, texelFetch at the fragment): the hemisphere lights'
                                  // lobe integrals, written once per frame by the lobe pass (SPEC_LOBE_MODE)
#define BINDING_LOBE_TABLES 8     // usamplerBuffer (RGBA32UI texel buffer, texelFetch): the hemisphere lights'
                                  // lobe tables, one per gloss
                                  // value of the scene's specular materials (shaders/lobe_lookup.h;
                                  // GpuMaterialBlock.lobe.x is a material's table's first entry)
#define BINDING_SHADOW_TRANSMITTANCE 10 // sampler2DArray (RGBA32F, texelFetch): coloured shadows — per shadow-map
                                        // layer, DEPTH_LAYERS layers of the optical-depth channels along the
                                        // light's ray to the nearest opaque surface, TRANSMITTANCE_MAP_SIZE²
                                        // (below, "Optical-depth channels"; read when SPEC_FILTERED_SHADOWS)
#define BINDING_SHADOW_EXCITATION 11    // samplerBuffer (RGBA32F texel buffer): per fluorescent material, per light,
                                        // its excitation integrand (rank-one: a filtered light's coupling is
                                        // Σ integrand·τ) or, with SPEC_FLUORESCENCE_SPECTRA, its matrix
                                        // (1/π)·D·E·Δλ (emission = Σ τ·row) — render/spectral_packing.h
                                        // (read when SPEC_FILTERED_SHADOWS)
#define BINDING_DEPTH_SPECTRA 12        // samplerBuffer (RGBA32F texel buffer): per optical-depth channel, BAND_LAYERS
                                        // vec4 of what turns it into log2 τ per band (below; read when
                                        // SPEC_FILTERED_SHADOWS or SPEC_VIEW_CHANNELS); after them, in the
                                        // response pass through transparent objects, the materials' response
                                        // spectra (GpuResponseBlock::spectra)
#define BINDING_SLAB_DISTANCE 14        // sampler2D (R32F, texelFetch): the nearest slab's distance per pixel (the slab
                                        // distance pass), by which the channel pass splits what lies in front of it
#define BINDING_VIEW_CHANNELS 13        // sampler2DArray (RGBA32F, texelFetch at the fragment): the camera's optical-depth
                                        // channels of the sheets and media in front of the opaque surface, written by
                                        // the channel pass (transmit.frag, CHANNEL_OUTPUT; read when SPEC_VIEW_CHANNELS)
#define BINDING_OPAQUE_DISTANCE 9 // sampler2D (R32F, texelFetch): the nearest opaque surface's distance per pixel,
                                  // written by the depth pre-pass (opaque_distance.frag) and read by the
                                  // transmission pass (transmit.frag) where a scene has transparent objects

// Shadow maps (docs/physics.md, "Shadows"): D32 layers of SHADOW_MAP_SIZE², depth-compared with
// no filtering; a fragment looks up its position pushed SHADOW_NORMAL_OFFSET texels along its face
// normal, and the depth pass adds a slope-scaled bias, so that no surface shadows itself.
#define SHADOW_MAP_SIZE 2048
#define MAX_SHADOW_LAYERS 96
#define SHADOW_NORMAL_OFFSET 1.0
// Coloured shadows: the transmittance maps' size (DEPTH_LAYERS RGBA32F layers per shadow-map layer).
#define TRANSMITTANCE_MAP_SIZE 256
#define MAX_DEPTH_CHANNELS 64  // optical-depth channels (below) a scene's coloured shadows may have
// Optical-depth channels (docs/physics.md, "Coloured shadows"). What a light's ray crosses on its
// way to a surface is summed per transparent material, not per band: a sheet's channel counts its
// crossings n (τ = T^n), a medium's holds its path ℓ in the frame's units (τ = 2^(−k·ℓ)), both
// linear, so the crossings add (blend one + one) and a bilinear lookup of the channels is the
// lookup of log2 τ band by band. A slab, whose T depends on the angle, has two: its crossings n and
// Σ cos θ, its factor n·log2 T(Σcos θ / n) evaluated per band. The channels: the sheets' and media's
// first (SPEC_DEPTH_CHANNELS), then the slabs' pairs (SPEC_SLAB_CHANNELS pairs); a material's first
// channel is GpuMaterialBlock::params.w. BINDING_DEPTH_SPECTRA holds per channel BAND_LAYERS vec4:
// a sheet's log2 T (≥ −149: a black band), a medium's −k (k = a·log2(10)·unit per unit), a slab's
// n(λ) and, in its second channel's, its attenuation a·d·log2(10). So a map's cost is the
// transparent area a light sees times ⌈channels / 4⌉ layers, whatever the number of bands.

// Descriptor set 1 of the spectral pass: the draw's material's textures (one set per material),
// RGBA32F 2D-array images read with texelFetch (bilinear filtering is done in the shader, in
// float, exactly as the CPU reference does it in double). Reflectance textures hold the grid's
// bands 4 per layer, like the target; the normal map is one layer of tangent-space xyz.
// Untextured slots hold a 1×1 placeholder that is never read.
#define TEXTURE_BINDING_DIFFUSE 0
#define TEXTURE_BINDING_SPECULAR 1
#define TEXTURE_BINDING_NORMAL 2
#define TEXTURE_BINDINGS 3

// Vertex attributes of the spectral pass (one interleaved buffer, 12 floats per vertex).
#define VERTEX_POSITION 0  // vec3, world space, metres
#define VERTEX_NORMAL 1    // vec3, world space
#define VERTEX_UV 2        // vec2, texture coordinates (u right, v down the image)
#define VERTEX_TANGENT 3   // vec4: xyz world-space tangent (direction of +u), w: bitangent sign
#define VERTEX_FLOATS 12
// Interreflection (shaders built with INDIRECT; docs/physics.md, "Interreflection"): a second
// vertex buffer of INDIRECT_VEC4 vec4 per vertex at locations VERTEX_INDIRECT …, this pass's bands
// of the indirect light at the element vertex — H/π, which the surface's own diffuse reflectance
// multiplies at the fragment, or for a fluorescent surface its whole re-sent radiance
// (ρd·H + M·H)/π — interpolated to the fragment at VARYING_INDIRECT …, W·sr⁻¹·m⁻²·nm⁻¹.
// After them, one vec4 more (INDIRECT_SHARE, the same in every pass): each emitter's share D/U of
// its direct light that reaches the vertex (GpuLightBlock's emitters, drawn per pixel; the H above
// then leaves their direct light out).
#define VERTEX_INDIRECT 4
#define VARYING_INDIRECT 4
#define INDIRECT_VEC4 8
#define INDIRECT_SHARE INDIRECT_VEC4                // its index in the record
#define INDIRECT_RECORD_VEC4 (INDIRECT_VEC4 + 1)    // vec4 per vertex and pass

// Specialization constants of spectral.frag: the shader is specialized to the scene. Lights are
// sorted ambient, then directional, then point, then hemisphere, so each kind is a loop without
// branches.
#define SPEC_AMBIENT_COUNT 0
#define SPEC_DIRECTIONAL_COUNT 1
#define SPEC_POINT_COUNT 2
#define SPEC_HAS_SPECULAR 3       // any material with a specular lobe
#define SPEC_HAS_FLUORESCENCE 4   // any fluorescent material
#define SPEC_HAS_TEXTURES 5       // any material with a diffuse or specular texture
#define SPEC_HAS_NORMAL_MAPS 6    // any material with a normal (or bump) map
#define SPEC_FLUORESCENCE_SPECTRA 7  // any Donaldson-matrix material: every fluorescent material's emission
                                     // comes from per-light spectra (GpuFluorescenceBlock), not coupling × ê/λ
#define SPEC_RESPONSES 8  // the response pass: the outputs are a detector's channels, not bands, summed from
                          // per-(material, light) response vectors (GpuResponseBlock; docs/color.md)
#define SPEC_HEMISPHERE_COUNT 9  // hemisphere lights (uniform sky or ground radiance), after the point lights
#define SPEC_SHADOWS 10          // any light casts shadows: the shadow maps are read
#define SPEC_LOBE_MODE 11        // LOBE_*: where the hemisphere lights' lobe integrals come from
// Which lights cast shadows and which hemisphere lights pair with the previous one are
// compile-time facts, not values read from a uniform block: lavapipe recompiles a shader whose
// control flow depends on its non-dynamic uniforms every frame (measured: ~35 ms per band pass).
// Shadowing lights come first among the directional and among the point lights.
#define SPEC_SHADOWED_DIRECTIONAL 12  // the first N directional lights cast shadows
#define SPEC_SHADOWED_POINT 13        // the first N point lights cast shadows
#define SPEC_HEMISPHERE_PAIRED 14     // bit i: hemisphere light i's up is opposite hemisphere light i−1's
// Coloured shadows: the scene has transparent objects and shadowing lights, so a shadowing light's
// spectrum is multiplied by its transmittance map at the receiver (BINDING_SHADOW_TRANSMITTANCE),
// and a rank-one fluorescent material's coupling is taken from the filtered light.
#define SPEC_FILTERED_SHADOWS 15
#define SPEC_BAND_LAYERS 16           // ⌈bands / 4⌉: the rows of each channel in BINDING_DEPTH_SPECTRA
// Interreflection's emitters drawn per pixel (GpuLightBlock::emitters x and y): constant, so that
// their loops unroll (a loop bounded by a uniform cost a 512² Cornell frame 30 ms more on lavapipe).
#define SPEC_EMITTER_TRIANGLES 17
#define SPEC_EMITTERS 18
// Any self-luminous material: without one, no band program tests a material's MATERIAL_EMITTER
// per fragment (a scene without emitters pays nothing for them).
#define SPEC_HAS_EMITTERS 19
// What the band passes compute (scene/surface_quantity.h): the radiance, or a ground-truth map —
// the illumination (ρd := 1, no specular, fluorescence or emission) or the reflectance ρd alone.
#define SPEC_QUANTITY 20
// Coloured shadows' optical-depth channels (above): the sheets' and media's, and the slabs' pairs.
#define SPEC_DEPTH_CHANNELS 21
#define SPEC_SLAB_CHANNELS 22
// The camera's transmission as channels: the band passes multiply their radiance by
// 2^(Σ c·k) from the first SPEC_VIEW_CHANNELS channels at the pixel (BINDING_VIEW_CHANNELS; 0: none,
// or the transmission passes multiply the target instead — a scene with slabs).
#define SPEC_VIEW_CHANNELS 23
// Coloured shadows through flat slabs: bit i set where slab i is flat (every normal of its objects
// parallel), so that under a directional light its T is one spectrum per shadow-map layer, computed
// in double once per scene (BINDING_DEPTH_SPECTRA from entry SPEC_SLAB_LAYER_ROWS:
// [layer][slab][band layer]), where elsewhere the shader evaluates Fresnel's equations per band.
#define SPEC_FLAT_SLABS 24
#define SPEC_SLAB_LAYER_ROWS 25
// The response pass through a slab (Scene::transparencyInResponses: one planar slab object): its
// first optical-depth channel (its n(λ) and attenuation rows in BINDING_DEPTH_SPECTRA), −1 none.
// Where the slab lies in front of the opaque surface (BINDING_SLAB_DISTANCE < BINDING_OPAQUE_DISTANCE)
// the response sums take its T(θ, λ) at the angle of the ray with GpuResponseBlock::slabNormal.
#define SPEC_VIEW_SLAB_CHANNEL 26
// The response pass through filters: the detector's channels (its records are padded to 4 per vec4;
// the padding's terms are zero and not summed), and the band layers [FIRST, END) where any of its
// weights is nonzero — every record outside them is exactly zero, so its terms are not summed.
#define SPEC_RESPONSE_CHANNELS 27
#define SPEC_RESPONSE_FIRST_LAYER 28
#define SPEC_RESPONSE_END_LAYER 29
// Single-crossing tables (render/crossing_tables.h; GpuResponseBlock::tables): the first row in
// BINDING_DEPTH_SPECTRA of their header — per sheet and medium channel e, vec4(1/h, nodes − 1, its
// first node, the largest depth tabulated or −1 for none) — or −1 for no tables; and the nodes of
// every channel together.
#define SPEC_CROSSING_HEADER 30
#define SPEC_CROSSING_NODES 31
#define QUANTITY_RADIANCE 0
#define QUANTITY_ILLUMINATION 1
#define QUANTITY_REFLECTANCE 2

// The hemisphere lights' lobe integrals are independent of wavelength but costly: with several band
// passes and at most MAX_LOBE_LIGHTS hemisphere lights, a lobe pass (one RGBA32F attachment, after
// the depth pre-pass) computes them once per pixel and the band passes read them.
#define LOBE_COMPUTE 0  // computed where they are used (one band pass, the response pass)
#define LOBE_WRITE 1    // the lobe pass: out0 = the integrals of hemisphere lights 0..3
#define LOBE_READ 2     // a band pass after the lobe pass: texelFetch at gl_FragCoord
#define MAX_LOBE_LIGHTS 4

struct GpuLight {
    vec4 vector;  // directional: xyz = unit vector towards the light; point: xyz = position in the
                  // scene's local frame (scene/local_frame.h), w = the frame's 1/unit² in m⁻² (1/d²
                  // in units times w is 1/d² in m⁻²); hemisphere: xyz = unit vector towards the
                  // middle of the hemisphere
    vec4 shadow;  // x: the light's first shadow-map layer, −1 if it casts no shadows; y: a texel's
                  // size, frame units (directional) or units per unit of distance (point). Whether it casts them is
                  // SPEC_SHADOWED_*, not this value (see there)
};

// Self-luminous surfaces whose direct light the INDIRECT programs draw per pixel (docs/physics.md,
// "Interreflection"): at most MAX_EMITTERS materials with MAX_EMITTER_TRIANGLES front triangles in
// all (radiosity/scene_radiosity.h). Each triangle's corners in the local frame, counter-clockwise
// seen from its front; corner 0's w is its emitter's index e, whose radiance L_e for this pass's
// bands is GpuLightSpectraBlock::lightBands[(emitters.z + e)·MAX_OUTPUTS + k].
#define MAX_EMITTERS 4
#define MAX_EMITTER_TRIANGLES 64

struct GpuLightBlock {
    GpuLight lights[MAX_LIGHTS];
    vec4 emitterCorners[3 * MAX_EMITTER_TRIANGLES];
    uvec4 emitters;  // x: triangles, y: emitters, z: their first entry in the light spectra (the scene's light count)
};

// World → clip of every shadow-map layer (depth 0..1, x and y to the layer's texture coordinates
// as (xy + 1)/2). A point light's six layers are the cube faces +x, −x, +y, −y, +z, −z.
struct GpuShadowBlock {
    mat4 layers[MAX_SHADOW_LAYERS];
};

// The shadow-map depth pass (shadow.vert).
struct ShadowPushConstants {
    mat4 lightViewProjection;
};

// E(λ) of every light for this pass's bands: lightBands[l * MAX_OUTPUTS + k] holds bands
// 4k..4k+3 of the pass (irradiance W·m⁻²·nm⁻¹, intensity W·sr⁻¹·nm⁻¹, or for a hemisphere
// light radiance W·sr⁻¹·m⁻²·nm⁻¹). Bands past the grid are 0.
struct GpuLightSpectraBlock {
    vec4 lightBands[MAX_LIGHTS * MAX_OUTPUTS];
};

// A material's switches: named bits of GpuMaterialBlock::switches.x, set by the packing
// (render/spectral_packing.cpp) and tested by the shader as (M.switches.x & BIT) != 0u.
#define MATERIAL_FLUORESCENT 1u       // re-emits (rank-one coupling or Donaldson spectra)
#define MATERIAL_SPECULAR 2u          // has a specular lobe (ρs not 0)
#define MATERIAL_DIFFUSE_TEXTURE 4u   // ρd (or its response) is multiplied by a texture
#define MATERIAL_SPECULAR_TEXTURE 8u  // ρs (or its response) likewise
#define MATERIAL_NORMAL_TEXTURE 16u   // a normal map perturbs the shading normal
#define MATERIAL_FILTER 32u           // a thin sheet: multiplies what is behind it by transmittance[]
#define MATERIAL_MEDIUM 64u           // an absorbing medium in a closed mesh: by exp2(−attenuation[]·ℓ)
#define MATERIAL_SLAB 128u            // a dielectric slab: Fresnel with ior[], internal exp2(−attenuation[]/cos θt)
#define MATERIAL_EMITTER 256u         // self-luminous: its front adds emitted[] (the band programs only)

struct GpuMaterialBlock {
    vec4 diffuse[MAX_OUTPUTS];             // ρd
    vec4 specular[MAX_OUTPUTS];            // ρs
    vec4 emissionOverLambda[MAX_OUTPUTS];  // ê(λ)/λ·2⁻ˢ, nm⁻² (0 for non-fluorescent materials);
                                           // s, per material, keeps the coupling near the
                                           // radiance's magnitude in float (docs/numerics.md)
    vec4 params;                           // x: gloss N; y: the texture layer of this pass's first
                                           // vec4; z: the material's first entry in
                                           // BINDING_SHADOW_EXCITATION, −1 if none; w: a transparent
                                           // material's first optical-depth channel, −1 else
    uvec4 switches;                        // x: MATERIAL_* bits (below); y, z, w: 0
    vec4 lobe;                             // x: the first entry of its lobe table in BINDING_LOBE_TABLES,
                                           // −1 if none; y, z: the table's x1 warp (lobeWarp, lobe_lookup.h)
    vec4 coupling[MAX_LIGHTS / 4];         // per light: (Φ/π)·Σ a·E·λ·Δλ·2ˢ (fluorescence)
    // Transparent materials (MATERIAL_FILTER, MATERIAL_MEDIUM, MATERIAL_SLAB; the transmission pass):
    // a sheet's transmittance per crossing; a medium's attenuation a·log2(10)·unit per unit of the
    // local frame (a the decadic absorbance per metre, unit the frame's unit in metres), so that a
    // path of ℓ units transmits exp2(−attenuation·ℓ), or a slab's a·d·log2(10) across its thickness
    // d (exp2(−attenuation/cos θt) along the refracted path); a slab's refractive index. 0 else.
    vec4 transmittance[MAX_OUTPUTS];
    vec4 attenuation[MAX_OUTPUTS];
    vec4 ior[MAX_OUTPUTS];
    // A self-luminous surface's radiance L_e, W·sr⁻¹·m⁻²·nm⁻¹, seen on its front; 0 else.
    vec4 emitted[MAX_OUTPUTS];
};

// The response pass (SPEC_RESPONSES): every term's geometric factor is independent of wavelength,
// so a detector's response to a pixel is, exactly, Σ_l [g/π·D_l + lobe·S_l + g·F_l] with, per
// (material, light), D_l = Σ_b w_cb·ρd_b·E_lb, S_l = Σ_b w_cb·ρs_b·E_lb and F_l the detector's
// response to the fluorescent radiance per unit g (w the detector's weights over the bands),
// computed once in double (render/spectral_packing.cpp). RESPONSE_VEC4 vec4 per light: up to
// 4·RESPONSE_VEC4 channels. Textured reflectances take D or S from the material's response
// texture instead: RESPONSE_VEC4 layers per light, texel by texel.
#define RESPONSE_VEC4 2
struct GpuResponseBlock {
    vec4 diffuse[MAX_LIGHTS * RESPONSE_VEC4];       // D_l: [l * RESPONSE_VEC4 + k]
    vec4 specular[MAX_LIGHTS * RESPONSE_VEC4];      // S_l
    vec4 fluorescence[MAX_LIGHTS * RESPONSE_VEC4];  // F_l
    // Seen through sheets and media (SPEC_VIEW_CHANNELS in the response pass): the radiance is
    // τ(λ)·L(λ), and its response Σ_b τ_b·(g/π·d_lcb + lobe·s_lcb) with the sums' terms kept per band,
    // d_lcb = w_cb·ρd_b·E_lb and s_lcb = w_cb·ρs_b·E_lb, in double rounded once to float. x: the first
    // row in BINDING_DEPTH_SPECTRA of this material's, C = 4·⌈channels/4⌉ channels × BAND_LAYERS vec4
    // (4 bands) per light and term: row x + ((2·l + term)·C + c)·BAND_LAYERS + j, term 0 diffuse,
    // 1 specular; −1 where there are none (a scene without transparent objects, a transparent material).
    // y (every block the same): with a slab, the first row of the detector-weighted light spectra
    // w_cb·E_lb, row y + (l·C + c)·BAND_LAYERS + j, that its reflection of the environment sums.
    // z: a rank-one fluorescent material's w_cb·ê_b/λ_b (scaled as GpuMaterialBlock's
    // emissionOverLambda), row z + c·BAND_LAYERS + j, times the fragment's summed coupling; −1 none.
    ivec4 spectra;
    vec4 slabNormal;  // xyz: the scene's one slab's unit normal, in the frame (with SPEC_VIEW_SLAB_CHANNEL)
    // Single-crossing tables (render/crossing_tables.h; SPEC_CROSSING_HEADER): x, this opaque
    // material's first row in BINDING_DEPTH_SPECTRA, per light l, term t (0 diffuse, 1 specular) and
    // node n of every channel's axis, F then h·F' as OC = ⌈channels/4⌉ vec4 each: row
    // x + ((2·l + t)·SPEC_CROSSING_NODES + n)·2·OC + {0, OC} + k; y: a rank-one fluorescent
    // material's emission table (w_cb·ê_b/λ_b), row y + n·2·OC + {0, OC} + k; z: that emission's
    // sum over the bands, OC vec4 (seen through nothing). −1: none.
    ivec4 tables;
};

// Fluorescence as per-light spectra, for scenes with a Donaldson-matrix material (a matrix does
// not factor into a coupling × a shape). It is view-independent per (material, light):
// F_l(λo) = (1/π)·Σᵢ D(λᵢ, λo)·E_l(λᵢ)·Δλ, the fluorescent radiance per unit geometric factor
// (W·sr⁻¹·m⁻²·nm⁻¹ for ambient and directional lights, W·sr⁻¹·nm⁻¹ for point lights), computed
// in double on the CPU for the matrix and the rank-one form alike; the shader adds g_l·F_l.
// emitted[l * MAX_OUTPUTS + k] holds bands 4k..4k+3 of this pass under light l. Records are laid
// out for the scene's light count (n lights: n·MAX_OUTPUTS vec4), the binding's range is the
// whole block and the shader reads only lights < n. Non-fluorescent materials share a record of
// zeros; scenes without matrices bind one such record and never read it.
struct GpuFluorescenceBlock {
    vec4 emitted[MAX_LIGHTS * MAX_OUTPUTS];
};

struct SpectralPushConstants {
    mat4 viewProjection;  // local frame → clip (Vulkan clip space, y down, depth 0..1)
    vec4 cameraPosition;  // xyz in the local frame; w = 1 perspective, 0 orthographic
    vec4 cameraForward;   // xyz: unit view direction (orthographic view vector is -forward)
    vec4 draw;            // the transmission pass, per draw: xyz = the point of the mesh's bounds nearest
                          // the camera (perspective) or its plane (orthographic), in the local frame, from
                          // which a medium's path is measured
};

// transmit.frag's specialization constants (its own ids).
#define TRANSMIT_SPEC_CHANNEL_OUTPUT 0    // write the optical-depth channels (the coloured shadows' maps, added)
#define TRANSMIT_SPEC_REFLECTION 1        // the slabs' reflection pass: add R·(the environment in the mirror direction)
#define TRANSMIT_SPEC_AMBIENT_COUNT 2     // the environment a slab reflects: the ambient lights (0 …)
#define TRANSMIT_SPEC_HEMISPHERE_FIRST 3  // and the hemisphere lights (their first index, their count)
#define TRANSMIT_SPEC_HEMISPHERE_COUNT 4
#define TRANSMIT_SPEC_FIRST_CHANNEL 5     // CHANNEL_OUTPUT: the channel of this pass's first output's x
// A scene with slabs and sheets or media: the channel pass writes two sets, the crossings behind the
// nearest slab (its first half of outputs) and in front of it (SPLIT); after the slabs' own draws,
// the nearest slab is drawn once more to multiply by the front set's τ (FRONT), which needs the
// channels' count and BAND_LAYERS (BINDING_DEPTH_SPECTRA's rows).
#define TRANSMIT_SPEC_SPLIT 6
#define TRANSMIT_SPEC_FRONT 7
#define TRANSMIT_SPEC_VIEW_CHANNELS 8
#define TRANSMIT_SPEC_BAND_LAYERS 9
// The response pass's slab reflection (with REFLECTION): the outputs are a detector's channels,
// Σ_j R_j(θ)·τ_front,j·(environment) against the detector-weighted light spectra
// (GpuResponseBlock::spectra.y), added to the response pass's.
#define TRANSMIT_SPEC_RESPONSES 10
// Its detector channels and band layers as spectral.frag's (SPEC_RESPONSE_CHANNELS …).
#define TRANSMIT_SPEC_RESPONSE_CHANNELS 11
#define TRANSMIT_SPEC_RESPONSE_FIRST_LAYER 12
#define TRANSMIT_SPEC_RESPONSE_END_LAYER 13

// ---------------------------------------------------------------------------------------------
// The tonemap pass (tonemap.frag): one fragment per output pixel reads the spectral target and
// evaluates the display path of color/tonemap.h.
#define TONEMAP_BINDING_SPECTRAL 0  // sampler2DArray: the spectral target (texelFetch only)
#define TONEMAP_BINDING_PARAMS 1    // TonemapParams (uniform)
#define TONEMAP_BINDING_TABLES 2    // vec4[] (storage): per-layer tables, offsets in TonemapParams

#define TONEMAP_MAX_CHANNELS 8      // detector channels (two RGBA32F response attachments)

// Specialization constants of tonemap.frag.
#define TONEMAP_SPEC_CHANNELS 0     // detector channels, 1..8
#define TONEMAP_SPEC_LAYERS 1       // spectral layers (4 bands each)
#define TONEMAP_SPEC_SSAA 2         // samples per pixel side in the spectral target
#define TONEMAP_SPEC_MODE 3         // TONEMAP_MODE_*
#define TONEMAP_SPEC_DISPLAY 4      // TONEMAP_DISPLAY_*
#define TONEMAP_SPEC_INPUT 5        // TONEMAP_INPUT_*: what the sampled target holds

#define TONEMAP_MODE_LINEAR 0
#define TONEMAP_MODE_FILM 1
#define TONEMAP_MODE_RESPONSES 2
#define TONEMAP_DISPLAY_SRGB 0
#define TONEMAP_DISPLAY_GOG 1
#define TONEMAP_INPUT_BANDS 0       // the spectral pass's bands, LAYERS layers
#define TONEMAP_INPUT_RESPONSES 1   // the response pass's detector channels, RESPONSE_VEC4 layers at most

// Colour attachments of the tonemap pass.
#define TONEMAP_OUT_COUNTS 0      // rgb: digital counts (integers as floats); a: 1 if clipped
#define TONEMAP_OUT_XYZ 1         // rgb: XYZ × output scale
#define TONEMAP_OUT_RESPONSES 2   // and 3: detector responses, 4 channels each

struct TonemapParams {
    vec4 responseToXyz[3];  // rows: relative XYZ = (dot(row0, r), dot(row1, r), dot(row2, r)), r = responses 0..2
    vec4 adaptation[3];     // rows of the chromatic adaptation matrix
    vec4 xyzToRgb[3];       // rows of the display's XYZ → linear RGB matrix
    vec4 blackXyz;          // xyz: display black; w: largest count (2^bits − 1)
    vec4 gain;              // GOG per channel (xyz)
    vec4 offset;
    vec4 gamma;
    vec4 cutoffCounts;      // xyz: counts at or below these show the display's black and are written 0
    vec4 filmCurve[3];      // per film layer: dMin, dMax, logH0, gamma (color/film.h, FilmCurve)
    vec4 filmToe;           // xyz: per film layer, the toe/shoulder width (density units)
    vec4 filmWhite;         // xyz: layer exposures of the reference white; w: 1 / projected clear-film Y
    vec4 scales;            // x: XYZ output scale; y: 1 / ssaa²
    uint weightsOffset;     // tables: [channel][layer] detector weights
    uint dyeOffset;         // tables: [dye][layer] film dye densities (yellow, magenta, cyan)
    uint baseOffset;        // tables: [layer] film base density
    uint projectionOffset;  // tables: [X,Y,Z][layer] lamp × colour matching × quadrature weight
};

#ifdef __cplusplus
// The C++ side of the vertex layout and of the specialization constants: the structs the engine
// fills, tied to the ids and counts above so that the pipeline's attribute and map entries come
// from here (render/spectral_resources.cpp, render/tonemap_pass.cpp) rather than being restated.
struct SpectralVertex {
    float position[3];  // VERTEX_POSITION
    float normal[3];    // VERTEX_NORMAL
    float uv[2];        // VERTEX_UV
    float tangent[4];   // VERTEX_TANGENT
};
static_assert(sizeof(SpectralVertex) == VERTEX_FLOATS * sizeof(float), "VERTEX_FLOATS floats per vertex");

// spectral.frag's specialization constants, in id order (SPEC_* = field index, 4 bytes each).
struct SpectralSpecialization {
    int32_t ambient, directional, point;  // SPEC_AMBIENT_COUNT, SPEC_DIRECTIONAL_COUNT, SPEC_POINT_COUNT
    uint32_t hasSpecular, hasFluorescence, hasTextures, hasNormalMaps, fluorescenceSpectra, responses;  // VkBool32
    int32_t hemisphere;  // SPEC_HEMISPHERE_COUNT
    uint32_t shadows;    // SPEC_SHADOWS
    int32_t lobeMode;    // SPEC_LOBE_MODE
    int32_t shadowedDirectional, shadowedPoint;  // SPEC_SHADOWED_DIRECTIONAL, SPEC_SHADOWED_POINT
    uint32_t hemispherePaired;                   // SPEC_HEMISPHERE_PAIRED
    uint32_t filteredShadows;                    // SPEC_FILTERED_SHADOWS (VkBool32)
    int32_t bandLayers;                          // SPEC_BAND_LAYERS
    int32_t emitterTriangles, emitters;          // SPEC_EMITTER_TRIANGLES, SPEC_EMITTERS
    uint32_t hasEmitters;                        // SPEC_HAS_EMITTERS (VkBool32)
    int32_t quantity;                            // SPEC_QUANTITY: QUANTITY_*
    int32_t depthChannels, slabChannels;         // SPEC_DEPTH_CHANNELS, SPEC_SLAB_CHANNELS
    int32_t viewChannels;                        // SPEC_VIEW_CHANNELS
    uint32_t flatSlabs;                          // SPEC_FLAT_SLABS
    int32_t slabLayerRows;                       // SPEC_SLAB_LAYER_ROWS
    int32_t viewSlabChannel;                     // SPEC_VIEW_SLAB_CHANNEL
    int32_t responseChannels;                    // SPEC_RESPONSE_CHANNELS
    int32_t responseFirstLayer, responseEndLayer;  // SPEC_RESPONSE_FIRST_LAYER, SPEC_RESPONSE_END_LAYER
    int32_t crossingHeader, crossingNodes;         // SPEC_CROSSING_HEADER, SPEC_CROSSING_NODES
};
static_assert(sizeof(SpectralSpecialization) == 4 * (SPEC_CROSSING_NODES + 1), "one 4-byte field per id");
static_assert(SPEC_AMBIENT_COUNT == 0 && SPEC_DIRECTIONAL_COUNT == 1 && SPEC_POINT_COUNT == 2 && SPEC_HAS_SPECULAR == 3 &&
                  SPEC_HAS_FLUORESCENCE == 4 && SPEC_HAS_TEXTURES == 5 && SPEC_HAS_NORMAL_MAPS == 6 &&
                  SPEC_FLUORESCENCE_SPECTRA == 7 && SPEC_RESPONSES == 8 && SPEC_HEMISPHERE_COUNT == 9 &&
                  SPEC_SHADOWS == 10 && SPEC_LOBE_MODE == 11 && SPEC_SHADOWED_DIRECTIONAL == 12 &&
                  SPEC_SHADOWED_POINT == 13 && SPEC_HEMISPHERE_PAIRED == 14 && SPEC_FILTERED_SHADOWS == 15 &&
                  SPEC_BAND_LAYERS == 16 && SPEC_EMITTER_TRIANGLES == 17 && SPEC_EMITTERS == 18 &&
                  SPEC_HAS_EMITTERS == 19 && SPEC_QUANTITY == 20 && SPEC_DEPTH_CHANNELS == 21 &&
                  SPEC_SLAB_CHANNELS == 22 && SPEC_VIEW_CHANNELS == 23 && SPEC_FLAT_SLABS == 24 &&
                  SPEC_SLAB_LAYER_ROWS == 25 && SPEC_VIEW_SLAB_CHANNEL == 26 &&
                  SPEC_RESPONSE_CHANNELS == 27 && SPEC_RESPONSE_FIRST_LAYER == 28 && SPEC_RESPONSE_END_LAYER == 29 &&
                  SPEC_CROSSING_HEADER == 30 && SPEC_CROSSING_NODES == 31,
              "SpectralSpecialization's fields are in id order");

// transmit.frag's specialization constants, in id order.
struct TransmitSpecialization {
    uint32_t channelOutput, reflection;                    // VkBool32
    int32_t ambientCount, hemisphereFirst, hemisphereCount;
    int32_t firstChannel;
    uint32_t split, front;  // VkBool32
    int32_t viewChannels, bandLayers;
    uint32_t responses;  // VkBool32
    int32_t responseChannels, responseFirstLayer, responseEndLayer;
};
static_assert(sizeof(TransmitSpecialization) == 4 * (TRANSMIT_SPEC_RESPONSE_END_LAYER + 1), "one 4-byte field per id");

// tonemap.frag's specialization constants, in id order.
struct TonemapSpecialization {
    int32_t channels, layers, ssaa, mode, display, input;  // TONEMAP_SPEC_CHANNELS … TONEMAP_SPEC_INPUT
};
static_assert(sizeof(TonemapSpecialization) == 4 * (TONEMAP_SPEC_INPUT + 1), "one 4-byte field per id");
static_assert(TONEMAP_SPEC_CHANNELS == 0 && TONEMAP_SPEC_LAYERS == 1 && TONEMAP_SPEC_SSAA == 2 && TONEMAP_SPEC_MODE == 3 &&
                  TONEMAP_SPEC_DISPLAY == 4 && TONEMAP_SPEC_INPUT == 5,
              "TonemapSpecialization's fields are in id order");

static_assert(sizeof(TonemapParams) == 16 * 20 + 16, "std140 layout");
static_assert(sizeof(GpuLightBlock) == 32 * MAX_LIGHTS + 48 * MAX_EMITTER_TRIANGLES + 16, "std140 layout");
static_assert(sizeof(GpuLightBlock) <= 16384, "must fit the minimum maxUniformBufferRange");
static_assert(sizeof(GpuShadowBlock) == 64 * MAX_SHADOW_LAYERS, "std140 layout");
static_assert(sizeof(ShadowPushConstants) == 64, "push constants must match GLSL");
static_assert(sizeof(GpuLightSpectraBlock) == 16384, "must fit the minimum maxUniformBufferRange");
static_assert(sizeof(GpuMaterialBlock) == 16 * (7 * MAX_OUTPUTS + 3 + MAX_LIGHTS / 4), "std140 layout");
static_assert(sizeof(GpuFluorescenceBlock) == 16384, "must fit the minimum maxUniformBufferRange");
static_assert(sizeof(GpuResponseBlock) <= 16384, "must fit the minimum maxUniformBufferRange");
static_assert(4 * RESPONSE_VEC4 == TONEMAP_MAX_CHANNELS, "the response pass carries every detector channel");
static_assert(sizeof(SpectralPushConstants) == 112, "push constants must match GLSL (≤ 128, Vulkan's minimum)");
}  // namespace metamer::gpu
#endif

#endif
