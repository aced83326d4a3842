#include "render/spectral_resources.h"

#include "interface.h"
#include "vk/barrier.h"

#include <algorithm>
#include <limits>

namespace metamer {

bool SpectralFrameState::cullable(const PackedDraw& d) const {
    // A closed mesh's back faces are hidden while the camera sees it whole from outside: every
    // corner of its bounds in front of the near plane (so that the plane cuts none of it open and
    // the camera is not inside). A margin covers the bounds' rounding to float.
    if (!d.closed) return false;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 p(corner & 1 ? d.upper.x : d.lower.x, corner & 2 ? d.upper.y : d.lower.y,
                          corner & 4 ? d.upper.z : d.lower.z);
        const glm::vec3 toCorner = p - camera.position;
        if (!(glm::dot(toCorner, camera.forward) > 1.01f * float(camera.nearPlane) + 1e-5f * glm::length(toCorner)))
            return false;
    }
    return true;
}

glm::vec3 SpectralFrameState::nearestPoint(const PackedDraw& d) const {
    if (camera.perspective) return glm::clamp(camera.position, d.lower, d.upper);
    glm::vec3 nearest = d.lower;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 p(corner & 1 ? d.upper.x : d.lower.x, corner & 2 ? d.upper.y : d.lower.y,
                          corner & 4 ? d.upper.z : d.lower.z);
        if (glm::dot(p - nearest, camera.forward) < 0.0f) nearest = p;
    }
    return nearest;
}

void SpectralResources::bindGeometry(VkCommandBuffer cmd, const SpectralFrameState& f) const {
    const VkDeviceSize zero = 0;
    const VkBuffer vb = vertexBuffer.handle();
    vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &zero);
    vkCmdBindIndexBuffer(cmd, indexBuffer.handle(), 0, VK_INDEX_TYPE_UINT32);
    vkCmdPushConstants(cmd, pipelineLayout.get(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                       sizeof(f.pc), &f.pc);
}

void SpectralResources::drawDepth(VkCommandBuffer cmd, const SpectralFrameState& f) const {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, depthPrePass.pipelines[0]);
    bindGeometry(cmd, f);
    VkPipeline bound = depthPrePass.pipelines[0];
    for (const PackedDraw& d : packed.draws) {
        if (d.transparent) continue;  // the opaque surfaces' depth only: transparent ones are seen through
        const VkPipeline pipeline = depthPrePass.pipelines[f.cullable(d) ? 1 : 0];
        if (pipeline != bound) vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, bound = pipeline);
        vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
    }
}

void SpectralResources::drawScene(VkCommandBuffer cmd, const SpectralFrameState& f, const std::vector<VkPipeline>& pipes,
                                  size_t p, VkDescriptorSet set0, bool specularOnly) const {
    bindGeometry(cmd, f);
    const size_t materials = packed.materials.size() / passes.size();
    VkPipeline bound = VK_NULL_HANDLE;
    for (const PackedDraw& d : packed.draws) {
        if (d.transparent) continue;  // drawn by the transmission pass
        const int32_t culled = materialCulledVariant[d.material];
        const uint32_t variant = culled >= 0 && f.cullable(d) ? uint32_t(culled) : materialVariant[d.material];
        if (specularOnly && !variants[variant].specular) continue;
        if (pipes[variant] != bound) {
            bound = pipes[variant];
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, bound);
        }
        uint32_t offsets[4] = {
            uint32_t(p * lightSpectraStride), uint32_t((p * materials + d.material) * materialStride),
            packed.fluorescenceSpectra
                ? uint32_t((p * packed.fluorescenceRecords + packed.fluorescenceRecord[d.material]) * fluorescenceStride)
                : 0u,
            packed.responses ? uint32_t(d.material * responseStride) : 0u};
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelineLayout.get(), 0, 1, &set0, 4, offsets);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelineLayout.get(), 1, 1,
                                &materialSets[d.material], 0, nullptr);
        vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
    }
}

void SpectralResources::drawTransparent(VkCommandBuffer cmd, const SpectralFrameState& f, size_t p, VkPipeline pipeline,
                                        VkDescriptorSet set0, VkPipeline reflection) const {
    bindGeometry(cmd, f);
    const size_t materials = packed.materials.size() / passes.size();
    std::vector<std::pair<float, const PackedDraw*>> order;
    for (const PackedDraw& d : packed.draws) {
        if (!d.transparent) continue;
        const glm::vec3 centre = 0.5f * (d.lower + d.upper);
        const float distance = f.camera.perspective ? glm::length(centre - f.camera.position)
                                                    : glm::dot(centre - f.camera.position, f.camera.forward);
        order.push_back({distance, &d});
    }
    std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    VkPipeline bound = VK_NULL_HANDLE;
    for (const auto& [distance, draw] : order) {
        const PackedDraw& d = *draw;
        gpu::SpectralPushConstants pc = f.pc;
        pc.draw = glm::vec4(f.nearestPoint(d), 0.0f);
        vkCmdPushConstants(cmd, pipelineLayout.get(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                           sizeof pc, &pc);
        const uint32_t offsets[4] = {uint32_t(p * lightSpectraStride), uint32_t((p * materials + d.material) * materialStride),
                                     0u, 0u};
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelineLayout.get(), 0, 1, &set0, 4, offsets);
        if (bound != pipeline) vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, bound = pipeline);
        vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
        if (reflection != VK_NULL_HANDLE && (packed.materials[d.material].switches.x & MATERIAL_SLAB) != 0u) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, bound = reflection);
            vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
        }
    }
}

void SpectralResources::declareFrame() {
    frame.clear();
    const VkExtent2D extent{plan.targetWidth, plan.targetHeight};
    const VkClearValue farDepth{.depthStencil = {1.0f, 0}};
    const bool draws = !packed.draws.empty();
    // With transparent objects the pre-pass also leaves the nearest opaque surface's distance
    // (background: the largest float) for the transmission passes.
    VkClearValue noSurface{};
    noSurface.color.float32[0] = std::numeric_limits<float>::max();
    if (hasDepthPrePass)
        frame.push_back({"depth pre-pass", hasTransmission ? "the opaque triangles" : "the scene's triangles",
                         hasTransmission ? "the depth and distance of the nearest opaque surface" : "the depth of the visible surface",
                         hasTransmission ? "opaque_distance.frag; back faces culled for closed meshes seen from outside"
                                         : "vertex stage only; back faces culled for closed meshes seen from outside",
                         depthPrePass.renderPass, depthPrePass.framebuffer.get(), extent,
                         hasTransmission ? std::vector<VkClearValue>{noSurface, farDepth} : std::vector<VkClearValue>{farDepth},
                         [this, draws](VkCommandBuffer cmd) {
                             if (draws) drawDepth(cmd, *frameState);
                         }});
    if (hasLobePass)
        // The hemisphere lights' lobe integrals, once per pixel, for every band pass to read.
        frame.push_back({"lobe pass", "the depth; the lobe tables", "the hemisphere lights' lobe integrals per pixel",
                         "LOBE_WRITE; specular materials' pipeline variants only", lobePass.renderPass, lobePass.framebuffer.get(), extent, {VkClearValue{}, VkClearValue{}},
                         [this, draws](VkCommandBuffer cmd) {
                             if (draws) drawScene(cmd, *frameState, lobePass.pipelines, 0, lobeDescriptorSet, true);
                         }});
    for (size_t p = 0; p < passes.size(); ++p) {
        const PassObjects& po = passes[p];
        std::vector<VkClearValue> clears(po.attachments + 1);
        for (uint32_t i = 0; i < po.attachments; ++i) clears[i].color = {{0, 0, 0, 0}};
        clears[po.attachments] = farDepth;
        const uint32_t first = po.firstLayer * 4,
                       last = std::min<uint32_t>(uint32_t(plan.bands), (po.firstLayer + po.attachments) * 4) - 1;
        frame.push_back({plan.responses ? "response pass" : fmt::format("band pass {}", p),
                         std::string(hasDepthPrePass ? "the depth; " : "") + (hasLobePass ? "the lobe integrals; " : "") +
                             "lights, materials, textures, shadow maps",
                         plan.responses ? fmt::format("the detector's {} channel(s)", plan.bands)
                                        : fmt::format("bands {}–{} (layers {}–{})", first, last, po.firstLayer,
                                                      po.firstLayer + po.attachments - 1),
                         fmt::format("OUTPUT_COUNT {}{}; a pipeline per material kind (specular, fluorescent, textured, "
                                     "normal-mapped, culled)",
                                     po.attachments, plan.responses ? ", SPEC_RESPONSES" : hasLobePass ? ", LOBE_READ" : ""),
                         po.renderPass, po.framebuffer.get(), extent, std::move(clears),
                         [this, p, draws](VkCommandBuffer cmd) {
                             if (draws) drawScene(cmd, *frameState, passes[p].pipelines, p, descriptorSet, false);
                         }});
        if (!hasTransmission) continue;
        const PassObjects& to = transmissionPasses[p];
        std::vector<VkClearValue> none(to.attachments + 1);
        frame.push_back({fmt::format("transmission pass {}", p), "band pass " + std::to_string(p) + "'s radiance; the opaque distance",
                         fmt::format("layers {}–{} × the transparent surfaces' transmittance", to.firstLayer,
                                     to.firstLayer + to.attachments - 1),
                         fmt::format("transmit.frag, OUTPUT_COUNT {}; farthest first, blend destination × source (slabs: then + their reflection)", to.attachments),
                         to.renderPass, to.framebuffer.get(), extent, std::move(none),
                         [this, p](VkCommandBuffer cmd) {
                             drawTransparent(cmd, *frameState, p, transmissionPasses[p].pipelines[0], descriptorSet,
                                             transmissionPasses[p].pipelines[1]);
                         }});
    }
}

void recordSpectralFrame(VkCommandBuffer cmd, const SpectralResources& r, const CameraMatrices& camera, size_t first,
                         size_t end) {
    end = std::min(end, r.frame.size());
    const SpectralPassPlan& plan = r.plan;
    const vk::Image& color = r.color;
    SpectralFrameState state{camera, {}};
    state.pc.viewProjection = camera.viewProjection;
    state.pc.cameraPosition = glm::vec4(camera.position, camera.perspective ? 1.0f : 0.0f);
    state.pc.cameraForward = glm::vec4(camera.forward, 0.0f);
    if (first == 0) {
        // Zero every layer (background radiance is 0), in GENERAL, then let the colour passes load it.
        const uint32_t layers = uint32_t(plan.layers);
        const vk::ImageUse previous{VK_IMAGE_LAYOUT_UNDEFINED,
                                    VK_ACCESS_HOST_READ_BIT | VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT,
                                    VK_PIPELINE_STAGE_ALL_COMMANDS_BIT};
        const vk::ImageUse cleared{VK_IMAGE_LAYOUT_GENERAL, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT};
        const vk::ImageUse drawn{VK_IMAGE_LAYOUT_GENERAL,
                                 VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                                 VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT};
        vk::imageBarrier(cmd, color.handle(), layers, previous, cleared);
        VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, layers};
        VkClearColorValue black{{0, 0, 0, 0}};
        vkCmdClearColorImage(cmd, color.handle(), VK_IMAGE_LAYOUT_GENERAL, &black, 1, &all);
        vk::imageBarrier(cmd, color.handle(), layers, cleared, drawn);
    }
    // The frame's declared passes, in order (SpectralResources::declareFrame).
    r.frameState = &state;
    for (size_t p = first; p < end; ++p) recordFramePass(cmd, r.frame[p]);
    r.frameState = nullptr;
    if (end < r.frame.size()) return;  // the rest of the frame follows in another submission
    if (plan.mappedReadback) {
        // Make the colour writes visible to the host, which reads the linear image directly.
        vk::imageBarrier(cmd, color.handle(), uint32_t(plan.layers),
                         {VK_IMAGE_LAYOUT_GENERAL, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                          VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT},
                         {VK_IMAGE_LAYOUT_GENERAL, VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_HOST_BIT});
    } else if (!plan.responses) {
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, uint32_t(plan.layers)};
        region.imageExtent = {plan.targetWidth, plan.targetHeight, 1};
        vkCmdCopyImageToBuffer(cmd, color.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, r.readbackBuffer.handle(), 1,
                               &region);
        vk::bufferBarrier(cmd, r.readbackBuffer.handle(), VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                          VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_HOST_BIT);
    }
}

}  // namespace metamer
