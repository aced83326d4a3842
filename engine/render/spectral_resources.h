// The Vulkan objects of one spectral pass, made once per scene from its packed data
// (render/spectral_packing.h) and plan, and the frame drawn with them. By concept, one file each:
//   spectral_resources.cpp    the frame's resources: buffers, textures, the layered colour target,
//                             depth, readback (what the passes read and write)
//   spectral_descriptors.cpp  descriptor set layouts, the pipeline layout and the sets
//   spectral_pipelines.cpp    each pass's render pass and pipelines (material variants)
//   shadow_pass.cpp, shadow_transmittance.cpp  the per-scene frames: shadow maps, coloured shadows
//   spectral_recording.cpp    the frame declared (render/frame_pass.h: passes and their resource
//                             uses; barriers derived) and its draws; recordSpectralFrame
// Everything is owned (vk/handle.h) and freed with the struct. Used by render/spectral_pass.cpp.
// Tests: through render/spectral_pass.h's (every GPU test runs with validation layers;
// tests/gpu_known_answer_test.cpp, tests/gpu_vs_reference_test.cpp), engine/render/frame_pass_test.cpp.
#pragma once

#include "interface.h"
#include "render/camera_matrices.h"
#include "render/frame_pass.h"
#include "render/spectral_packing.h"
#include "render/transmittance_map_cost.h"
#include "render/spectral_plan.h"
#include "render/target_readback.h"
#include "scene/scene.h"
#include "scene/scene_on_grid.h"
#include "vk/context.h"
#include "vk/device_objects.h"
#include "vk/handle.h"
#include "vk/pipeline.h"
#include "vk/render_pass.h"
#include "vk/resources.h"

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace metamer {

// What a frame's passes record with: the camera and the push constants made from it.
struct SpectralFrameState {
    const CameraMatrices& camera;
    gpu::SpectralPushConstants pc;
    // Whether the draw's back faces may be culled from this camera (a closed mesh seen whole from outside).
    bool cullable(const PackedDraw& d) const;
    // The point of the draw's bounds nearest the camera (the camera's own position inside them), or,
    // orthographic, the corner nearest the camera's plane: where a medium's path is measured from.
    glm::vec3 nearestPoint(const PackedDraw& d) const;
    // The transparent draws farthest first (by their bounds' centres), sorted once per frame on
    // first use: a frame with slabs draws them in three passes, a scene may hold 10⁵ of them.
    mutable std::vector<std::pair<float, const PackedDraw*>> transparentOrder;
    mutable bool transparentOrdered = false;
};

struct SpectralResources {
    // One render pass of up to MAX_OUTPUTS attachments (layers firstLayer …), or the depth pre-pass
    // (attachments 0). Passes with the same attachment count share a render pass and pipelines:
    // one per material variant (the depth pre-pass: one).
    struct PassObjects {
        uint32_t firstLayer = 0, attachments = 0;
        VkRenderPass renderPass = VK_NULL_HANDLE;
        std::vector<VkPipeline> pipelines;  // [variant] (the depth pre-pass: back faces kept, culled)
        vk::OwnedFramebuffer framebuffer;
    };
    // What a draw compiles in: lavapipe runs every branch a SIMD batch reaches, taken or not, so a
    // fragment shader specialized to the scene would pay for a specular lobe, a hemisphere light's
    // lobe lookup, fluorescence or textures on every pixel if any material had them. Each distinct
    // kind of material is a pipeline variant, and again with back faces culled for the closed
    // meshes that have it (drawn so while the camera is outside their bounds: their back faces are
    // hidden then, and culling them saves their rasterization and any shading before the front
    // face covers them). Draws bind their variant's pipeline.
    struct Variant {
        bool specular = false, fluorescent = false, textures = false, normalMap = false;
        bool cullBackFaces = false;
        bool operator==(const Variant&) const = default;
    };
    std::vector<Variant> variants;
    // Per material: its variant, and the same with back faces culled (its closed meshes), or −1.
    std::vector<uint32_t> materialVariant;
    std::vector<int32_t> materialCulledVariant;

    // Makes every object; `plan` gets mappedReadback (whether the target is read by mapping).
    SpectralResources(vk::Context& ctx, const Scene& scene, const SceneOnGrid& spectra, const PackedScene& packed,
                      SpectralPassPlan& plan, const SpectralPassOptions& options);

    // The target drawn last, as host memory (made visible to the host first).
    LayeredView mapTarget();

    vk::Context& ctx;
    const Scene& scene;
    const PackedScene& packed;
    const SpectralPassPlan& plan;

    vk::Buffer vertexBuffer, indexBuffer, lightBuffer, lightSpectraBuffer, materialBuffer, fluorescenceBuffer,
        responseBuffer, readbackBuffer, lobeTableBuffer;
    // Interreflection: packed.indirect, bound as vertex buffer 1 at pass p's part (indirectPassBytes each).
    vk::Buffer indirectBuffer;
    VkDeviceSize indirectPassBytes = 0;
    vk::OwnedBufferView lobeTableView;  // the lobe tables as a texel buffer of RGBA32UI
    // Dynamic-offset strides.
    VkDeviceSize lightSpectraStride = 0, materialStride = 0, fluorescenceStride = 0, responseStride = 0;
    vk::Image color, depth;
    // The shadow maps (render/shadow_maps.h), drawn once when the resources are made — they depend
    // on the scene, not the camera — and read by the spectral passes through a depth-compare
    // sampler; a 1×1 placeholder when no light casts shadows. render/shadow_pass.cpp.
    std::shared_ptr<vk::Image> shadowMap;  // shared with later renders of the same geometry and lights
    vk::Buffer shadowBuffer;  // GpuShadowBlock
    vk::OwnedSampler shadowSampler;
    double shadowMs = 0.0;    // the depth passes' time
    TransmittanceMapCost transmittanceCost;  // the coloured shadows' maps, estimated before drawing
    // Textures (one image per SceneOnGrid texture, or per response texture in the response pass,
    // then a placeholder) and one descriptor set of set 1 per material.
    std::vector<vk::Image> textures;
    std::vector<std::array<int, 3>> materialTextures;  // per material: diffuse, specular, normal texture
    vk::OwnedSampler textureSampler;
    // Shared with every pass of the same configuration (vk/device_objects.h).
    vk::SharedHandle<VkDescriptorSetLayout> setLayout, textureSetLayout;
    vk::SharedHandle<VkPipelineLayout> pipelineLayout;
    vk::OwnedDescriptorPool descriptorPool;  // frees the sets with it
    VkDescriptorSet descriptorSet = VK_NULL_HANDLE;
    // The lobe pass (interface.h, LOBE_*): after the depth pre-pass, one RGBA32F attachment of the
    // hemisphere lights' lobe integrals that the band passes read; it draws with its own set 0,
    // whose BINDING_LOBE_WEIGHTS is the placeholder (an image is never read while drawn into).
    bool hasLobePass = false;
    vk::Image lobeWeights;
    VkDescriptorSet lobeDescriptorSet = VK_NULL_HANDLE;
    std::vector<VkDescriptorSet> materialSets;
    vk::OwnedShaderModule vert, vertIndirect;  // spectral.vert, and its INDIRECT build with interreflection
    std::vector<vk::SharedHandle<VkRenderPass>> renderPasses;  // the depth pre-pass's, then one per attachment count
    std::vector<vk::SharedHandle<VkPipeline>> pipelines;
    // The band passes share a depth pre-pass, so that each shades a pixel once whatever the
    // overdraw. The response pass has one, too, only with textured materials (createPasses says
    // why); otherwise it writes depth itself in its one pass (LESS_OR_EQUAL keeps the last of
    // equal depths, as EQUAL after the pre-pass does, so it shades the same surface).
    bool hasDepthPrePass = true;
    PassObjects depthPrePass, lobePass;
    std::vector<PassObjects> passes;
    // The transmission passes (shaders/transmit.frag), one after each band pass where the scene has
    // transparent objects: the same layers, blended destination × source, reading the nearest opaque
    // surface's distance that the depth pre-pass then writes too (opaqueDistance, R32F;
    // opaque_distance.frag, BINDING_OPAQUE_DISTANCE). A pipeline each, no material variants.
    bool hasTransmission = false;
    vk::Image opaqueDistance;
    // Where the transparent objects are sheets and media only (no slab, whose reflection must be
    // added in depth order), the camera's transmission is a channel pass instead: one draw of each
    // transparent object into viewChannelLayers layers of optical-depth channels (viewChannels,
    // RGBA32F, BINDING_VIEW_CHANNELS), which the band passes turn into τ per band and multiply
    // their radiance by (SPEC_VIEW_CHANNELS) — no transmission pass. 0: the transmission passes.
    uint32_t viewChannelLayers = 0;
    vk::Image viewChannels;
    PassObjects viewChannelPass;
    // With slabs as well (viewSplit): a slab distance pass first (the nearest slab's distance,
    // slabDistance R32F, by its own depth), the channel pass writes two sets — behind the nearest
    // slab (layers 0 … L−1, which the band passes apply) and in front of it (L … 2L−1) — and after
    // each band pass the transmission pass draws only the slabs (T, then their reflection), then the
    // nearest slab once more multiplying by the front set's τ (transmit.frag, FRONT).
    bool viewSplit = false;
    // The response pass through the scene's one slab: its material's first optical-depth channel
    // (SPEC_VIEW_SLAB_CHANNEL; −1: none).
    int32_t viewSlabChannel = -1;
    VkDescriptorSet channelDescriptorSet = VK_NULL_HANDLE;  // set 0 with a placeholder for the view channels
    vk::Image slabDistance, slabDepth;
    PassObjects slabDistancePass;
    // Coloured shadows (packed.filteredShadows): per shadow-map layer, packed.depthLayers layers of
    // the optical-depth channels along the light's rays to the nearest opaque surface
    // (TRANSMITTANCE_MAP_SIZE², RGBA32F; interface.h), drawn once per scene like the shadow maps —
    // from each light, the same distance pre-pass as from the camera, then the transparent objects
    // adding their channels (transmit.frag, CHANNEL_OUTPUT), into lightDistance (R32F) and
    // shadowTransmittance — and read by the band passes (BINDING_SHADOW_TRANSMITTANCE) with the
    // channels' spectra (BINDING_DEPTH_SPECTRA); the rank-one fluorescent materials' excitation
    // integrands as a texel buffer (BINDING_SHADOW_EXCITATION).
    vk::Image shadowTransmittance, lightDistance, lightDepth;
    vk::Buffer shadowExcitationBuffer, depthSpectraBuffer;
    vk::OwnedBufferView shadowExcitationView, depthSpectraView;
    VkDescriptorSet lightDescriptorSet = VK_NULL_HANDLE;  // set 0 with the light's distance
    std::vector<PassObjects> transmissionPasses;
    // The response pass through filters in two draws (bandSplit). lavapipe runs a fragment
    // program's every instruction at every pixel of a block, a loop's body included where no pixel
    // runs it, and skips only what its early depth test rejects (docs/performance.md). So every
    // pixel is drawn first without the per-band sums (spectral.frag RESPONSES_WITHOUT_BANDS), which
    // writes the depth of the pixels that need them into bandPassDepthColor (R32F, 0 elsewhere);
    // copied through bandDepthBuffer into bandDepth (D32), it is the depth the full program is then
    // drawn against (EQUAL, passes[0]'s render pass and pipelines, bandFramebuffer): only those
    // pixels are shaded again, and each takes the value the one-draw pass gave it.
    bool bandSplit = false;
    PassObjects responsesWithoutBands;
    vk::Image bandPassDepthColor, bandDepth;
    vk::Buffer bandDepthBuffer;
    vk::OwnedFramebuffer bandFramebuffer;

    // The frame as declared passes over declared resources (render/frame_pass.h), recorded in
    // order by recordSpectralFrame with the barriers derived from the declarations: each pass names
    // the resources it uses and how, its render pass, framebuffer and clears (its pipelines are its
    // shader's specializations, one per material variant), and records its commands. A new pass is
    // one entry in declareFrame, its render pass and pipelines, and its shader.
    Frame frame;
    size_t targetResource = 0;  // the layered colour target's index in frame.resources()
    // The camera's state while recordSpectralFrame records the frame (the passes' draws read it).
    mutable const SpectralFrameState* frameState = nullptr;
    // "clear → depth pre-pass → lobe pass → band pass 0 → band pass 1 … → host read"
    std::string describeFrame() const { return frame.describe(); }

private:
    VkDeviceSize aligned(VkDeviceSize size) const;
    vk::Buffer uniforms(const void* data, size_t size, size_t count, VkDeviceSize stride, const char* name);
    void createBuffers();
    void createShadowMaps();
    void drawShadowMaps(vk::Image& image, uint32_t size, uint32_t layers);  // the depth passes into `image`
    void createTextures(std::vector<const TextureOnGrid*> list);
    void createTargets(Readback mode, bool sampled, SpectralPassPlan& plan);
    void createLayouts();
    // bandDepthOutput: one more attachment, R32F cleared to 0 (the response pass's first draw).
    VkRenderPass makeRenderPass(uint32_t attachments, bool clearsDepth, bool bandDepthOutput = false);
    // withoutBands: the RESPONSES_WITHOUT_BANDS program, with that attachment.
    VkPipeline makePipeline(const vk::SharedHandle<VkRenderPass>& renderPass, uint32_t attachments, bool writesDepth,
                            int lobeMode, const Variant& variant, bool withoutBands = false);
    std::vector<VkPipeline> makePipelines(const vk::SharedHandle<VkRenderPass>& renderPass, uint32_t attachments,
                                          bool writesDepth, int lobeMode, bool withoutBands = false);
    void classifyDraws();
    void createLobePass();
    void createTransmissionPasses();
    void createViewChannelPass();
    VkRenderPass channelRenderPass(uint32_t attachments);
    VkPipeline makeChannelPipeline(VkRenderPass renderPass, uint32_t attachments, uint32_t size, int32_t firstChannel,
                                   bool split);
    void createDistancePrePass();
    void createShadowTransmittanceImages();
    void drawShadowTransmittance();
    vk::RenderPassDesc distancePrePassDesc() const;
    // size: the square target's side (the transmittance maps'), 0 for the spectral target's.
    vk::GraphicsPipelineDesc transparentPipelineDesc(VkRenderPass renderPass, uint32_t attachments, uint32_t size = 0) const;
    VkPipeline makeOwnPipeline(const std::string& key, vk::GraphicsPipelineDesc d, const uint32_t* code, size_t bytes,
                               const VkSpecializationInfo* specialization = nullptr);
    void createPasses();
    void declareFrame();
    // What every drawing pass reads that was made once per scene (settled, never written in a
    // frame): geometry, set 0's uniform and texel buffers, the shadow maps, the textures, and —
    // `transmittanceMaps` — the coloured shadows' maps.
    struct SceneReads {
        std::vector<ResourceUse> geometry, shading;
        std::vector<ResourceUse> all() const {  // what a shading pass reads: both
            std::vector<ResourceUse> uses = geometry;
            uses.insert(uses.end(), shading.begin(), shading.end());
            return uses;
        }
    };
    SceneReads declareSceneReads(Frame& f, bool transmittanceMaps) const;
    // The draws the frame's passes record.
    void bindGeometry(VkCommandBuffer cmd, const SpectralFrameState& f) const;
    void drawDepth(VkCommandBuffer cmd, const SpectralFrameState& f) const;
    // Every draw of band pass p (the lobe pass draws as pass 0, with its own set 0), with its
    // material's pipeline variant: this pass's bands of the light spectra, of the draw's material
    // and of its fluorescence; the material's responses (the response pass). `specularOnly`: only
    // the draws of materials with a specular lobe (the lobe pass: nothing else reads its weights).
    void drawScene(VkCommandBuffer cmd, const SpectralFrameState& f, const std::vector<VkPipeline>& pipelines, size_t p,
                   VkDescriptorSet set0, bool specularOnly) const;
    // The transparent draws of transmission pass p, each with its material's pass-p bands and the
    // point its medium's path is measured from (SpectralPushConstants::draw).
    // Back to front (by their bounds' centres), so that a slab's reflection, added after its
    // transmittance multiplied what is behind it, is itself multiplied by what is in front;
    // `reflection`: the slabs' second, additive draw (VK_NULL_HANDLE: none, as from a light);
    // `which`: the kinds drawn; `front`: after them all, every slab drawn again with it (the
    // nearest one multiplying by what lies in front of it, viewSplit).
    enum class TransparentDraws { All, Slabs, SheetsAndMedia };
    void drawTransparent(VkCommandBuffer cmd, const SpectralFrameState& f, size_t p, VkPipeline pipeline,
                         VkDescriptorSet set0, VkPipeline reflection = VK_NULL_HANDLE,
                         TransparentDraws which = TransparentDraws::All, VkPipeline front = VK_NULL_HANDLE) const;
};

// A frame's commands: the declared passes in order (SpectralResources::frame: the clear, the depth
// pre-pass, the lobe pass, every colour pass, the readback copy or the host's read; the response
// pass's target is left for the tonemap pass), each after the barriers derived for it. [first, end)
// records only those passes: a frame submitted pass by pass (SpectralPass::draw with a progress
// callback) records the same commands in pieces.
void recordSpectralFrame(VkCommandBuffer cmd, const SpectralResources& r, const CameraMatrices& camera,
                         size_t first = 0, size_t end = SIZE_MAX);

}  // namespace metamer
