// Coloured shadows (packed.filteredShadows): the transmittance maps drawn once per scene, from each
// shadow-map layer's light — the opaque surfaces' distance, then the transparent surfaces' optical
// depth in front of them, band group by band group — as a Frame of declared passes
// (render/frame_pass.h), read by the band passes through BINDING_SHADOW_TRANSMITTANCE
// (docs/physics.md, "Transparent objects").
// Tests: tests/transparency_test.cpp (coloured shadows against the CPU reference).
#include "render/spectral_resources.h"

#include "core/timing.h"
#include "interface.h"
#include "render/spectral_shaders.h"
#include "vk/pipeline.h"
#include "vk/render_pass.h"

#include <limits>
#include <map>
#include <memory>

namespace metamer {

// The coloured shadows' images: the transmittance maps (per shadow-map layer, every band layer) and
// the light's distance pre-pass targets, TRANSMITTANCE_MAP_SIZE².
void SpectralResources::createShadowTransmittanceImages() {
    const uint32_t size = TRANSMITTANCE_MAP_SIZE;
    const uint32_t layers = uint32_t(packed.shadowMaps.layers.size()) * uint32_t(packed.bandLayers);
    if (layers > ctx.properties().limits.maxImageArrayLayers)
        failInput(Where{scene.file.string(), "lights", 0},
                  "coloured shadows need a transmittance layer per shadow-map layer ({}) and per 4 bands ({}): {} layers, "
                  "beyond this device's {}; cast shadows from fewer lights (\"shadows\": false), or render fewer bands",
                  packed.shadowMaps.layers.size(), packed.bandLayers, layers, ctx.properties().limits.maxImageArrayLayers);
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
// from each shadow-map layer's light, the opaque surfaces' distance (opaque_distance.frag) and then,
// band group by band group, the transparent surfaces' product in front of them (transmit.frag) —
// the camera's transmission, seen from the light — into that layer's transmittance layers.
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
    // One render pass and pipeline per attachment count: clear to 0, add the optical depths.
    std::map<uint32_t, std::pair<VkRenderPass, VkPipeline>> byCount;
    for (const PassObjects& band : passes) {
        if (byCount.count(band.attachments)) continue;
        vk::RenderPassDesc desc;
        for (uint32_t i = 0; i < band.attachments; ++i)
            desc.colors.push_back(
                vk::attachmentFor(VK_FORMAT_R32G32B32A32_SFLOAT, vk::Access::ColorAttachment, VK_ATTACHMENT_LOAD_OP_CLEAR));
        renderPasses.push_back(vk::sharedRenderPass(
            ctx.objects(), fmt::format("spectral.shadow transmittance attachments={}", band.attachments), desc));
        const VkRenderPass rp = renderPasses.back().get();
        const SpirvCode code = transmitFragment(band.attachments);
        vk::GraphicsPipelineDesc pd = transparentPipelineDesc(rp, band.attachments, size);
        pd.multiplyBlend = false;
        pd.addBlend = true;  // optical depths add (transmit.frag, LOG_OUTPUT)
        const uint32_t logOutput = VK_TRUE;
        const VkSpecializationMapEntry entry{0, 0, sizeof logOutput};
        const VkSpecializationInfo si{1, &entry, sizeof logOutput, &logOutput};
        const VkPipeline pl = makeOwnPipeline(
            fmt::format("spectral.shadow transmittance attachments={} {}x{} pass={} layout={} log", band.attachments, size,
                        size, static_cast<void*>(rp), static_cast<void*>(pipelineLayout.get())),
            pd, code.code, code.bytes, &si);
        byCount[band.attachments] = {rp, pl};
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
    const VkClearValue clear{};  // optical depth 0: nothing in the way
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
        for (size_t p = 0; p < passes.size(); ++p) {
            const auto [rp, pl] = byCount.at(passes[p].attachments);
            std::vector<VkImageView> views;
            const uint32_t first = uint32_t(layer) * uint32_t(packed.bandLayers) + passes[p].firstLayer;
            for (uint32_t i = 0; i < passes[p].attachments; ++i) views.push_back(shadowTransmittance.layerView(first + i));
            framebuffers.push_back(vk::createFramebuffer(ctx.device(), rp, views, size, size));
            const VkPipeline pipeline = pl;
            std::vector<ResourceUse> uses = transmission;
            uses.push_back({maps, vk::Access::ColorAttachment, first, passes[p].attachments, false});
            lightPasses.add(FramePass{fmt::format("shadow transmittance {} band pass {}", layer, p),
                                   "transmit.frag, LOG_OUTPUT (optical depths add)", std::move(uses), rp,
                                   framebuffers.back().get(), {size, size},
                                   std::vector<VkClearValue>(passes[p].attachments, clear),
                                   [this, f, p, pipeline](VkCommandBuffer cmd) {
                                       drawTransparent(cmd, *f, p, pipeline, lightDescriptorSet);
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
