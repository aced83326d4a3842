// Coloured shadows (packed.filteredShadows): the transmittance maps drawn once per scene, from each
// shadow-map layer's light — the opaque surfaces' distance, then the transparent surfaces in front
// of them adding their optical-depth channels (interface.h: per transparent material, not per band)
// — as a Frame of declared passes (render/frame_pass.h), read by the band passes through
// BINDING_SHADOW_TRANSMITTANCE with BINDING_DEPTH_SPECTRA (docs/physics.md, "Coloured shadows").
// Tests: tests/transparency_test.cpp (coloured shadows against the CPU reference).
#include "render/spectral_resources.h"

#include "core/timing.h"
#include "interface.h"
#include "render/spectral_shaders.h"
#include "vk/pipeline.h"
#include "vk/render_pass.h"

#include <algorithm>
#include <limits>
#include <memory>

namespace metamer {

// The coloured shadows' images: the transmittance maps (per shadow-map layer, the channels' layers)
// and the light's distance pre-pass targets, TRANSMITTANCE_MAP_SIZE².
void SpectralResources::createShadowTransmittanceImages() {
    const uint32_t size = TRANSMITTANCE_MAP_SIZE;
    const uint32_t layers = uint32_t(packed.shadowMaps.layers.size()) * uint32_t(packed.depthLayers);
    if (layers > ctx.properties().limits.maxImageArrayLayers)
        failInput(Where{scene.file.string(), "lights", 0},
                  "coloured shadows need a transmittance layer per shadow-map layer ({}) and per 4 optical-depth "
                  "channels ({}): {} layers, beyond this device's {}; cast shadows from fewer lights (\"shadows\": false)",
                  packed.shadowMaps.layers.size(), packed.depthLayers, layers, ctx.properties().limits.maxImageArrayLayers);
    vk::ImageDesc t;
    t.width = t.height = size;
    t.layers = layers;
    t.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    t.name = "shadow transmittance";
    shadowTransmittance = vk::Image(ctx, t);
    vk::ImageDesc dist;
    dist.format = VK_FORMAT_R32_SFLOAT;
    dist.width = dist.height = size;
    dist.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    dist.name = "light distance";
    lightDistance = vk::Image(ctx, dist);
    vk::ImageDesc depthDesc;
    depthDesc.format = VK_FORMAT_D32_SFLOAT;
    depthDesc.width = depthDesc.height = size;
    depthDesc.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    depthDesc.name = "light depth";
    lightDepth = vk::Image(ctx, depthDesc);
}

// Coloured shadows, drawn once per scene (they depend on the lights and objects, not the camera):
// from each shadow-map layer's light, the opaque surfaces' distance (opaque_distance.frag) and then
// the transparent surfaces in front of them, each adding its crossing to its material's channels
// (transmit.frag, CHANNEL_OUTPUT), in groups of at most MAX_OUTPUTS layers (one group below 33
// channels) — so each transparent object is drawn once per light and group, whatever the bands.
void SpectralResources::drawShadowTransmittance() {
    auto t0 = Clock::now();
    const uint32_t size = TRANSMITTANCE_MAP_SIZE;
    renderPasses.push_back(vk::sharedRenderPass(ctx.objects(), fmt::format("spectral.distance pre-pass {}x{}", size, size),
                                                distancePrePassDesc()));
    const VkRenderPass distancePass = renderPasses.back().get();
    vk::GraphicsPipelineDesc dd = transparentPipelineDesc(distancePass, 1, size);
    dd.depthTest = dd.depthWrite = true;
    dd.depthCompare = VK_COMPARE_OP_LESS;
    dd.multiplyBlend = false;
    const VkPipeline distancePipeline = makeOwnPipeline(
        fmt::format("spectral.light distance {}x{} pass={} layout={}", size, size, static_cast<void*>(distancePass),
                    static_cast<void*>(pipelineLayout.get())),
        dd, opaqueDistanceFragment().code, opaqueDistanceFragment().bytes);
    const vk::OwnedFramebuffer distanceFramebuffer =
        vk::createFramebuffer(ctx.device(), distancePass, {lightDistance.layerView(0), lightDepth.layerView(0)}, size, size);
    // The groups of channel layers, each a render pass of up to MAX_OUTPUTS attachments: cleared to
    // 0 (nothing crossed), the channels added.
    struct Group {
        uint32_t firstLayer, attachments;
        VkRenderPass renderPass;
        VkPipeline pipeline;
    };
    std::vector<Group> groups;
    for (uint32_t first = 0; first < uint32_t(packed.depthLayers); first += MAX_OUTPUTS) {
        const uint32_t attachments = std::min<uint32_t>(MAX_OUTPUTS, uint32_t(packed.depthLayers) - first);
        const VkRenderPass rp = channelRenderPass(attachments);
        groups.push_back({first, attachments, rp, makeChannelPipeline(rp, attachments, size, int32_t(4 * first), false)});
    }
    std::vector<vk::OwnedFramebuffer> framebuffers;
    // The frame: the light's distance and depth are its own, rewritten per light; the maps are
    // made here for the band passes to sample in every later frame.
    Frame lightPasses;
    const size_t distance = lightPasses.add(FrameResource::perFrame("light distance", lightDistance.handle()));
    const size_t depthImage =
        lightPasses.add(FrameResource::perFrame("light depth", lightDepth.handle(), 1, VK_IMAGE_ASPECT_DEPTH_BIT));
    const size_t maps = lightPasses.add(FrameResource::madeFor("shadow transmittance", shadowTransmittance.handle(),
                                                               shadowTransmittance.desc().layers, {vk::Access::Sampled}));
    const SceneReads scene = declareSceneReads(lightPasses, false);
    std::vector<ResourceUse> transmission = scene.all();
    transmission.push_back({distance, vk::Access::Sampled});
    std::vector<std::unique_ptr<CameraMatrices>> eyes;
    std::vector<std::unique_ptr<SpectralFrameState>> states;
    const VkClearValue farDepth{.depthStencil = {1.0f, 0}};
    VkClearValue noSurface{};
    noSurface.color.float32[0] = std::numeric_limits<float>::max();
    const VkClearValue clear{};  // every channel 0: nothing in the way
    for (size_t layer = 0; layer < packed.shadowMaps.layers.size(); ++layer) {
        // The light as the passes' "camera": a point light's position (distances from it), or a
        // directional light's travel (distances along it, from the frame's origin).
        const glm::vec4 eye = packed.shadowEyes[layer];
        auto cm = std::make_unique<CameraMatrices>();
        cm->viewProjection = packed.shadowBlock.layers[layer];
        cm->perspective = eye.w > 0.5f;
        cm->position = cm->perspective ? glm::vec3(eye) : glm::vec3(0.0f);
        cm->forward = cm->perspective ? glm::vec3(0.0f, 0.0f, -1.0f) : glm::vec3(eye);
        auto state = std::make_unique<SpectralFrameState>(SpectralFrameState{*cm, {}});
        state->pc.viewProjection = cm->viewProjection;
        state->pc.cameraPosition = glm::vec4(cm->position, cm->perspective ? 1.0f : 0.0f);
        state->pc.cameraForward = glm::vec4(cm->forward, 0.0f);
        const SpectralFrameState* f = state.get();
        std::vector<ResourceUse> distanceUses = scene.geometry;
        distanceUses.push_back({distance, vk::Access::ColorAttachment, 0, kAllLayers, false});
        distanceUses.push_back({depthImage, vk::Access::DepthAttachment, 0, kAllLayers, false});
        lightPasses.add(FramePass{fmt::format("light distance {}", layer), "opaque_distance.frag", std::move(distanceUses),
                               distancePass, distanceFramebuffer.get(), {size, size}, {noSurface, farDepth},
                               [this, f, distancePipeline](VkCommandBuffer cmd) {
                                   vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, distancePipeline);
                                   bindGeometry(cmd, *f);
                                   for (const PackedDraw& d : packed.draws)
                                       if (!d.transparent) vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
                               }});
        for (size_t gi = 0; gi < groups.size(); ++gi) {
            const Group& group = groups[gi];
            std::vector<VkImageView> views;
            const uint32_t first = uint32_t(layer) * uint32_t(packed.depthLayers) + group.firstLayer;
            for (uint32_t i = 0; i < group.attachments; ++i) views.push_back(shadowTransmittance.layerView(first + i));
            framebuffers.push_back(vk::createFramebuffer(ctx.device(), group.renderPass, views, size, size));
            const VkPipeline pipeline = group.pipeline;
            std::vector<ResourceUse> uses = transmission;
            uses.push_back({maps, vk::Access::ColorAttachment, first, group.attachments, false});
            // The material blocks of band pass 0: a material's channel (params.w) is the same in every pass.
            lightPasses.add(FramePass{fmt::format("shadow transmittance {} channel group {}", layer, gi),
                                   "transmit.frag, CHANNEL_OUTPUT (the channels add)", std::move(uses), group.renderPass,
                                   framebuffers.back().get(), {size, size},
                                   std::vector<VkClearValue>(group.attachments, clear),
                                   [this, f, pipeline](VkCommandBuffer cmd) {
                                       drawTransparent(cmd, *f, 0, pipeline, lightDescriptorSet);
                                   }});
        }
        eyes.push_back(std::move(cm));
        states.push_back(std::move(state));
    }
    lightPasses.derive();
    ctx.submitAndWait([&](VkCommandBuffer cmd) { recordFrame(cmd, lightPasses); });
    shadowMs += msSince(t0);
}


}  // namespace metamer
