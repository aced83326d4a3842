#include "render/spectral_resources.h"

#include "interface.h"
#include "vk/barrier.h"

#include <tuple>

namespace metamer {

void recordSpectralFrame(VkCommandBuffer cmd, const SpectralResources& r, const CameraMatrices& camera) {
    const auto& [vertexBuffer, indexBuffer, color, readbackBuffer] =
        std::tie(r.vertexBuffer, r.indexBuffer, r.color, r.readbackBuffer);
    const PackedScene& packed = r.packed;
    const SpectralPassPlan& plan = r.plan;
    const VkPipelineLayout pipelineLayout = r.pipelineLayout.get();
    gpu::SpectralPushConstants pc{};
    pc.viewProjection = camera.viewProjection;
    pc.cameraPosition = glm::vec4(camera.position, camera.perspective ? 1.0f : 0.0f);
    pc.cameraForward = glm::vec4(camera.forward, 0.0f);
    VkDeviceSize zero = 0;
    VkBuffer vb = vertexBuffer.handle();
    // A closed mesh's back faces are hidden while the camera sees it whole from outside: every
    // corner of its bounds in front of the near plane (so that the plane cuts none of it open and
    // the camera is not inside). A margin covers the bounds' rounding to float.
    auto cullable = [&](const PackedDraw& d) {
        if (!d.closed) return false;
        for (int corner = 0; corner < 8; ++corner) {
            const glm::vec3 p(corner & 1 ? d.upper.x : d.lower.x, corner & 2 ? d.upper.y : d.lower.y,
                              corner & 4 ? d.upper.z : d.lower.z);
            const glm::vec3 toCorner = p - camera.position;
            if (!(glm::dot(toCorner, camera.forward) > 1.01f * float(camera.nearPlane) + 1e-5f * glm::length(toCorner)))
                return false;
        }
        return true;
    };
    {
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
    if (r.hasDepthPrePass) {
        VkClearValue clear{};
        clear.depthStencil = {1.0f, 0};
        VkRenderPassBeginInfo rb{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
        rb.renderPass = r.depthPrePass.renderPass;
        rb.framebuffer = r.depthPrePass.framebuffer.get();
        rb.renderArea = {{0, 0}, {plan.targetWidth, plan.targetHeight}};
        rb.clearValueCount = 1;
        rb.pClearValues = &clear;
        vkCmdBeginRenderPass(cmd, &rb, VK_SUBPASS_CONTENTS_INLINE);
        if (!packed.draws.empty()) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, r.depthPrePass.pipelines[0]);
            vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &zero);
            vkCmdBindIndexBuffer(cmd, indexBuffer.handle(), 0, VK_INDEX_TYPE_UINT32);
            vkCmdPushConstants(cmd, pipelineLayout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                               sizeof(pc), &pc);
            VkPipeline bound = r.depthPrePass.pipelines[0];
            for (const PackedDraw& d : packed.draws) {
                const VkPipeline pipeline = r.depthPrePass.pipelines[cullable(d) ? 1 : 0];
                if (pipeline != bound) vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, bound = pipeline);
                vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
            }
        }
        vkCmdEndRenderPass(cmd);
    }
    // Every draw of band pass p (the lobe pass draws as pass 0, with its own set 0), with its
    // material's pipeline variant: this pass's bands of the light spectra, of the draw's material
    // and of its fluorescence; the material's responses (the response pass). `specularOnly`: only
    // the draws of materials with a specular lobe (the lobe pass: nothing else reads its weights).
    auto drawScene = [&](const std::vector<VkPipeline>& pipelines, size_t p, VkDescriptorSet set0, bool specularOnly) {
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &zero);
        vkCmdBindIndexBuffer(cmd, indexBuffer.handle(), 0, VK_INDEX_TYPE_UINT32);
        vkCmdPushConstants(cmd, pipelineLayout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(pc),
                           &pc);
        const size_t materials = packed.materials.size() / r.passes.size();
        VkPipeline bound = VK_NULL_HANDLE;
        for (const PackedDraw& d : packed.draws) {
            const int32_t culled = r.materialCulledVariant[d.material];
            const uint32_t variant = culled >= 0 && cullable(d) ? uint32_t(culled) : r.materialVariant[d.material];
            if (specularOnly && !r.variants[variant].specular) continue;
            if (pipelines[variant] != bound) {
                bound = pipelines[variant];
                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, bound);
            }
            uint32_t offsets[4] = {
                uint32_t(p * r.lightSpectraStride), uint32_t((p * materials + d.material) * r.materialStride),
                packed.fluorescenceSpectra
                    ? uint32_t((p * packed.fluorescenceRecords + packed.fluorescenceRecord[d.material]) * r.fluorescenceStride)
                    : 0u,
                packed.responses ? uint32_t(d.material * r.responseStride) : 0u};
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelineLayout, 0, 1, &set0, 4, offsets);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelineLayout, 1, 1,
                                    &r.materialSets[d.material], 0, nullptr);
            vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
        }
    };
    if (r.hasLobePass) {
        // The hemisphere lights' lobe integrals, once per pixel, for every band pass to read.
        VkClearValue clears[2] = {};
        VkRenderPassBeginInfo rb{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
        rb.renderPass = r.lobePass.renderPass;
        rb.framebuffer = r.lobePass.framebuffer.get();
        rb.renderArea = {{0, 0}, {plan.targetWidth, plan.targetHeight}};
        rb.clearValueCount = 2;
        rb.pClearValues = clears;
        vkCmdBeginRenderPass(cmd, &rb, VK_SUBPASS_CONTENTS_INLINE);
        if (!packed.draws.empty()) drawScene(r.lobePass.pipelines, 0, r.lobeDescriptorSet, true);
        vkCmdEndRenderPass(cmd);
    }
    for (size_t p = 0; p < r.passes.size(); ++p) {
        const SpectralResources::PassObjects& po = r.passes[p];
        std::vector<VkClearValue> clears(po.attachments + 1);
        for (uint32_t i = 0; i < po.attachments; ++i) clears[i].color = {{0, 0, 0, 0}};
        clears[po.attachments].depthStencil = {1.0f, 0};
        VkRenderPassBeginInfo rb{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
        rb.renderPass = po.renderPass;
        rb.framebuffer = po.framebuffer.get();
        rb.renderArea = {{0, 0}, {plan.targetWidth, plan.targetHeight}};
        rb.clearValueCount = uint32_t(clears.size());
        rb.pClearValues = clears.data();
        vkCmdBeginRenderPass(cmd, &rb, VK_SUBPASS_CONTENTS_INLINE);
        if (!packed.draws.empty()) drawScene(po.pipelines, p, r.descriptorSet, false);
        vkCmdEndRenderPass(cmd);
    }
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
        vkCmdCopyImageToBuffer(cmd, color.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readbackBuffer.handle(), 1,
                               &region);
        vk::bufferBarrier(cmd, readbackBuffer.handle(), VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                          VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_HOST_BIT);
    }
}

}  // namespace metamer
