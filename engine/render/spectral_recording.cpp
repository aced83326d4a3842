#include "render/spectral_resources.h"

#include "interface.h"

#include <algorithm>
#include <limits>

namespace metamer {

bool SpectralFrameState::cullable(const PackedDraw& d) const {
    // A closed mesh's back faces are hidden while the camera sees it whole from outside: every
    // corner of its bounds in front of the near plane (so that the plane cuts none of it open and
    // the camera is not inside). A margin covers the bounds' rounding to float.
    if (d.alwaysCull) return true;  // one side of an interreflected open mesh, its other side a copy of its own
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
    if (!specularOnly && indirectBuffer.handle() != VK_NULL_HANDLE && !plan.responses) {
        const VkBuffer b = indirectBuffer.handle();
        const VkDeviceSize offset = p * indirectPassBytes;
        vkCmdBindVertexBuffers(cmd, 1, 1, &b, &offset);
    }
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
                                        VkDescriptorSet set0, VkPipeline reflection, TransparentDraws which,
                                        VkPipeline front) const {
    bindGeometry(cmd, f);
    const size_t materials = packed.materials.size() / passes.size();
    if (!f.transparentOrdered) {
        f.transparentOrder.clear();
        for (const PackedDraw& d : packed.draws) {
            if (!d.transparent) continue;
            const glm::vec3 centre = 0.5f * (d.lower + d.upper);
            const float distance = f.camera.perspective ? glm::length(centre - f.camera.position)
                                                        : glm::dot(centre - f.camera.position, f.camera.forward);
            f.transparentOrder.push_back({distance, &d});
        }
        std::stable_sort(f.transparentOrder.begin(), f.transparentOrder.end(),
                         [](const auto& a, const auto& b) { return a.first > b.first; });
        f.transparentOrdered = true;
    }
    auto wanted = [&](const PackedDraw& d) {
        const bool slab = (packed.materials[d.material].switches.x & MATERIAL_SLAB) != 0u;
        return !((which == TransparentDraws::Slabs && !slab) || (which == TransparentDraws::SheetsAndMedia && slab));
    };
    const auto& order = f.transparentOrder;
    VkPipeline bound = VK_NULL_HANDLE;
    // A scene of 10⁵ sheets is 10⁵ draws: each binds its material only where it changes, and pushes
    // the point its path is measured from only for a medium (the one kind that reads it).
    uint32_t boundMaterial = ~0u;
    auto bindMaterial = [&](uint32_t material) {
        if (material == boundMaterial) return;
        boundMaterial = material;
        const uint32_t offsets[4] = {uint32_t(p * lightSpectraStride), uint32_t((p * materials + material) * materialStride),
                                     0u, 0u};
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelineLayout.get(), 0, 1, &set0, 4, offsets);
    };
    for (const auto& [distance, draw] : order) {
        const PackedDraw& d = *draw;
        if (!wanted(d)) continue;
        if ((packed.materials[d.material].switches.x & MATERIAL_MEDIUM) != 0u) {
            gpu::SpectralPushConstants pc = f.pc;
            pc.draw = glm::vec4(f.nearestPoint(d), 0.0f);
            vkCmdPushConstants(cmd, pipelineLayout.get(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                               sizeof pc, &pc);
        }
        bindMaterial(d.material);
        if (bound != pipeline) vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, bound = pipeline);
        vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
        if (reflection != VK_NULL_HANDLE && (packed.materials[d.material].switches.x & MATERIAL_SLAB) != 0u) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, bound = reflection);
            vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
        }
    }
    if (front == VK_NULL_HANDLE) return;
    // After every slab has multiplied and added: the nearest one, again, multiplies by what lies in
    // front of it (its fragments elsewhere are discarded).
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, front);
    for (const auto& [distance, draw] : order) {
        const PackedDraw& d = *draw;
        if ((packed.materials[d.material].switches.x & MATERIAL_SLAB) == 0u) continue;
        bindMaterial(d.material);
        vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
    }
}

SpectralResources::SceneReads SpectralResources::declareSceneReads(Frame& f, bool transmittanceMaps) const {
    SceneReads reads;
    auto buffer = [&](std::vector<ResourceUse>& into, const char* name, const vk::Buffer& b, vk::Access access) {
        if (b.handle() != VK_NULL_HANDLE) into.push_back({f.add(FrameResource::settled(name, b.handle(), access)), access});
    };
    buffer(reads.geometry, "vertices", vertexBuffer, vk::Access::VertexInput);
    buffer(reads.geometry, "indices", indexBuffer, vk::Access::VertexInput);
    buffer(reads.geometry, "indirect light", indirectBuffer, vk::Access::VertexInput);
    const struct {
        const char* name;
        const vk::Buffer& buffer;
    } uniforms[] = {{"lights", lightBuffer},         {"light spectra", lightSpectraBuffer},
                    {"materials", materialBuffer},   {"fluorescence", fluorescenceBuffer},
                    {"responses", responseBuffer},   {"shadow matrices", shadowBuffer},
                    {"lobe tables", lobeTableBuffer}, {"shadow excitation", shadowExcitationBuffer},
                    {"optical-depth spectra", depthSpectraBuffer}};
    for (const auto& u : uniforms) buffer(reads.shading, u.name, u.buffer, vk::Access::UniformRead);
    auto image = [&](std::string name, const vk::Image& im, bool depthAspect) {
        const vk::Use sampled{vk::Access::Sampled, true, depthAspect};
        reads.shading.push_back(
            {f.add(FrameResource::settled(std::move(name), im.handle(), im.desc().layers, sampled)), vk::Access::Sampled});
    };
    image("shadow maps", *shadowMap, true);
    for (size_t t = 0; t < textures.size(); ++t)
        image(t + 1 == textures.size() ? "placeholder texture" : fmt::format("texture {}", t), textures[t], false);
    if (transmittanceMaps && packed.filteredShadows) image("shadow transmittance", shadowTransmittance, false);
    return reads;
}

void SpectralResources::declareFrame() {
    using vk::Access;
    frame.clear();
    const VkExtent2D extent{plan.targetWidth, plan.targetHeight};
    const VkClearValue farDepth{.depthStencil = {1.0f, 0}};
    const bool draws = !packed.draws.empty();
    const uint32_t layers = uint32_t(plan.layers);
    // The frame's own images and buffers: drawn in every frame, first written (cleared) in it.
    targetResource = frame.add(FrameResource::perFrame("spectral target", color.handle(), layers));
    const size_t depthImage = frame.add(FrameResource::perFrame("depth", depth.handle(), 1, VK_IMAGE_ASPECT_DEPTH_BIT));
    const size_t distance = hasTransmission ? frame.add(FrameResource::perFrame("opaque distance", opaqueDistance.handle())) : 0;
    const size_t lobe = hasLobePass ? frame.add(FrameResource::perFrame("lobe weights", lobeWeights.handle())) : 0;
    const size_t channels =
        viewChannelLayers > 0 ? frame.add(FrameResource::perFrame("view channels", viewChannels.handle(), viewChannelLayers)) : 0;
    const size_t slabs = viewSplit ? frame.add(FrameResource::perFrame("slab distance", slabDistance.handle())) : 0;
    const size_t slabsDepth =
        viewSplit ? frame.add(FrameResource::perFrame("slab depth", slabDepth.handle(), 1, VK_IMAGE_ASPECT_DEPTH_BIT)) : 0;
    const size_t bandColor =
        bandSplit ? frame.add(FrameResource::perFrame("band pass depth (R32F)", bandPassDepthColor.handle())) : 0;
    const size_t bandBuffer = bandSplit ? frame.add(FrameResource::perFrame("band pass depth copy", bandDepthBuffer.handle())) : 0;
    const size_t bandDepthImage =
        bandSplit ? frame.add(FrameResource::perFrame("band pass depth", bandDepth.handle(), 1, VK_IMAGE_ASPECT_DEPTH_BIT)) : 0;
    const bool copies = !plan.mappedReadback && !plan.responses;
    const size_t readback = copies ? frame.add(FrameResource::perFrame("readback buffer", readbackBuffer.handle())) : 0;
    const SceneReads scene = declareSceneReads(frame, true);
    auto with = [](std::vector<ResourceUse> uses, const std::vector<ResourceUse>& more) {
        uses.insert(uses.end(), more.begin(), more.end());
        return uses;
    };
    const std::vector<ResourceUse> shading = scene.all();

    // Zero every layer (background radiance is 0) before the colour passes load it: a transfer, not
    // a render pass's clear — lavapipe (Mesa 22.3) leaks about a target's size of memory per
    // render-pass clear of array-layer views (measured: +20 MB per frame at 256² × 89 bands).
    frame.add(FramePass{"clear", "vkCmdClearColorImage", {{targetResource, Access::TransferDst, 0, kAllLayers, false}},
                        VK_NULL_HANDLE, VK_NULL_HANDLE, {}, {}, [this, layers](VkCommandBuffer cmd) {
                            const VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, layers};
                            const VkClearColorValue black{{0, 0, 0, 0}};
                            vkCmdClearColorImage(cmd, color.handle(), vk::accessLayout(Access::TransferDst), &black, 1, &all);
                        }});
    if (hasDepthPrePass) {
        // With transparent objects the pre-pass also leaves the nearest opaque surface's distance
        // (background: the largest float) for the transmission passes.
        VkClearValue noSurface{};
        noSurface.color.float32[0] = std::numeric_limits<float>::max();
        std::vector<ResourceUse> uses = with({{depthImage, Access::DepthAttachment, 0, kAllLayers, false}}, scene.geometry);
        if (hasTransmission) uses.push_back({distance, Access::ColorAttachment, 0, kAllLayers, false});
        frame.add(FramePass{"depth pre-pass",
                            hasTransmission ? "opaque_distance.frag; back faces culled for closed meshes seen from outside"
                                            : "vertex stage only; back faces culled for closed meshes seen from outside",
                            std::move(uses), depthPrePass.renderPass, depthPrePass.framebuffer.get(), extent,
                            hasTransmission ? std::vector<VkClearValue>{noSurface, farDepth} : std::vector<VkClearValue>{farDepth},
                            [this, draws](VkCommandBuffer cmd) {
                                if (draws) drawDepth(cmd, *frameState);
                            }});
    }
    // spectral.frag declares the opaque and slab distances (the response pass through a slab reads
    // them): every pass that binds it samples them, whichever program is bound.
    // (The lobe pass runs before the slab distance pass writes: only the opaque distance there.)
    std::vector<ResourceUse> distances;
    if (hasTransmission) distances.push_back({distance, Access::Sampled});
    if (hasLobePass)
        // The hemisphere lights' lobe integrals, once per pixel, for every band pass to read.
        frame.add(FramePass{"lobe pass", "LOBE_WRITE; specular materials' pipeline variants only",
                            with(with({{depthImage, Access::DepthAttachment}, {lobe, Access::ColorAttachment, 0, kAllLayers, false}},
                                      shading),
                                 distances),
                            lobePass.renderPass, lobePass.framebuffer.get(), extent, {VkClearValue{}, VkClearValue{}},
                            [this, draws](VkCommandBuffer cmd) {
                                if (draws) drawScene(cmd, *frameState, lobePass.pipelines, 0, lobeDescriptorSet, true);
                            }});
    if (viewSplit) {
        // The nearest slab's distance (by its own depth), to split the crossings in front of it.
        VkClearValue noSlab{};
        noSlab.color.float32[0] = std::numeric_limits<float>::max();
        frame.add(FramePass{"slab distance pass", "opaque_distance.frag, the slabs only",
                            with({{slabs, Access::ColorAttachment, 0, kAllLayers, false},
                                  {slabsDepth, Access::DepthAttachment, 0, kAllLayers, false}},
                                 scene.geometry),
                            slabDistancePass.renderPass, slabDistancePass.framebuffer.get(), extent, {noSlab, farDepth},
                            [this](VkCommandBuffer cmd) {
                                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, slabDistancePass.pipelines[0]);
                                bindGeometry(cmd, *frameState);
                                for (const PackedDraw& d : packed.draws)
                                    if (d.transparent && (packed.materials[d.material].switches.x & MATERIAL_SLAB) != 0u)
                                        vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
                            }});
    }
    if (viewChannelLayers > 0) {
        // What the camera sees through, per transparent material, once per frame for every band pass.
        std::vector<ResourceUse> uses =
            with({{channels, Access::ColorAttachment, 0, kAllLayers, false}, {distance, Access::Sampled}}, shading);
        if (viewSplit) uses.push_back({slabs, Access::Sampled});
        frame.add(FramePass{"channel pass",
                            viewSplit ? "transmit.frag, CHANNEL_OUTPUT, SPLIT (behind and in front of the nearest slab)"
                                      : "transmit.frag, CHANNEL_OUTPUT (the channels add)",
                            std::move(uses), viewChannelPass.renderPass, viewChannelPass.framebuffer.get(), extent,
                            std::vector<VkClearValue>(viewChannelLayers), [this](VkCommandBuffer cmd) {
                                drawTransparent(cmd, *frameState, 0, viewChannelPass.pipelines[0], channelDescriptorSet,
                                                VK_NULL_HANDLE, TransparentDraws::SheetsAndMedia);
                            }});
    }
    for (size_t p = 0; p < passes.size(); ++p) {
        const PassObjects& po = passes[p];
        std::vector<VkClearValue> clears(po.attachments + 1);
        for (uint32_t i = 0; i < po.attachments; ++i) clears[i].color = {{0, 0, 0, 0}};
        clears[po.attachments] = farDepth;
        std::vector<ResourceUse> reads = shading;
        if (hasLobePass) reads.push_back({lobe, Access::Sampled});
        if (viewChannelLayers > 0) reads.push_back({channels, Access::Sampled});
        reads.insert(reads.end(), distances.begin(), distances.end());
        if (viewSplit) reads.push_back({slabs, Access::Sampled});
        const ResourceUse target{targetResource, Access::ColorAttachment, po.firstLayer, po.attachments};
        // Without a pre-pass, the pass clears and writes its own depth.
        ResourceUse depthUse{depthImage, Access::DepthAttachment, 0, kAllLayers, hasDepthPrePass};
        if (bandSplit) {
            // The response pass through filters in two draws (spectral_resources.h, bandSplit):
            // every pixel without the per-band sums, writing the depth of those that need them …
            std::vector<ResourceUse> firstUses =
                with({target, depthUse, {bandColor, Access::ColorAttachment, 0, kAllLayers, false}}, reads);
            std::vector<VkClearValue> firstClears(po.attachments + 2);
            firstClears[po.attachments].color = {{0, 0, 0, 0}};
            firstClears[po.attachments + 1] = farDepth;
            frame.add(FramePass{"response pass, without bands",
                                fmt::format("OUTPUT_COUNT {}, SPEC_RESPONSES, RESPONSES_WITHOUT_BANDS; + the depth of the "
                                            "pixels that need the per-band sums (R32F, 0 elsewhere)",
                                            po.attachments),
                                std::move(firstUses), responsesWithoutBands.renderPass,
                                responsesWithoutBands.framebuffer.get(), extent, std::move(firstClears),
                                [this, draws](VkCommandBuffer cmd) {
                                    if (draws) drawScene(cmd, *frameState, responsesWithoutBands.pipelines, 0, descriptorSet, false);
                                }});
            // … that depth into a depth image (a colour image cannot be copied into one directly) …
            frame.add(FramePass{"band pass depth copy", "vkCmdCopyImageToBuffer",
                                {{bandColor, Access::TransferSrc}, {bandBuffer, Access::TransferDst, 0, kAllLayers, false}},
                                VK_NULL_HANDLE, VK_NULL_HANDLE, {}, {}, [this](VkCommandBuffer cmd) {
                                    const VkBufferImageCopy region{0, 0, 0, {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1}, {0, 0, 0},
                                                                   {plan.targetWidth, plan.targetHeight, 1}};
                                    vkCmdCopyImageToBuffer(cmd, bandPassDepthColor.handle(), vk::accessLayout(Access::TransferSrc),
                                                           bandDepthBuffer.handle(), 1, &region);
                                }});
            frame.add(FramePass{"band pass depth", "vkCmdCopyBufferToImage",
                                {{bandBuffer, Access::TransferSrc}, {bandDepthImage, Access::TransferDst, 0, kAllLayers, false}},
                                VK_NULL_HANDLE, VK_NULL_HANDLE, {}, {}, [this](VkCommandBuffer cmd) {
                                    const VkBufferImageCopy region{0, 0, 0, {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 0, 1}, {0, 0, 0},
                                                                   {plan.targetWidth, plan.targetHeight, 1}};
                                    vkCmdCopyBufferToImage(cmd, bandDepthBuffer.handle(), bandDepth.handle(),
                                                           vk::accessLayout(Access::TransferDst, true), 1, &region);
                                }});
            // … and the full program again where that depth is the surface's (EQUAL): the early depth
            // test keeps it off every other pixel.
            depthUse = {bandDepthImage, Access::DepthAttachment, 0, kAllLayers, true};
        }
        std::vector<ResourceUse> uses = with({target, depthUse}, reads);
        frame.add(FramePass{plan.responses ? (bandSplit ? "response pass, the pixels that sum bands" : "response pass")
                                           : fmt::format("band pass {}", p),
                            fmt::format("OUTPUT_COUNT {}{}; a pipeline per material kind (specular, fluorescent, textured, "
                                        "normal-mapped, culled)",
                                        po.attachments, plan.responses ? ", SPEC_RESPONSES" : hasLobePass ? ", LOBE_READ" : ""),
                            std::move(uses), po.renderPass, bandSplit ? bandFramebuffer.get() : po.framebuffer.get(),
                            extent, std::move(clears), [this, p, draws](VkCommandBuffer cmd) {
                                if (draws) drawScene(cmd, *frameState, passes[p].pipelines, p, descriptorSet, false);
                            }});
        if (!hasTransmission || (viewChannelLayers > 0 && !viewSplit)) continue;
        const PassObjects& to = transmissionPasses[p];
        std::vector<ResourceUse> transmissionUses =
            with({{targetResource, Access::ColorAttachment, to.firstLayer, to.attachments}, {distance, Access::Sampled}},
                 shading);
        if (viewSplit) {
            transmissionUses.push_back({slabs, Access::Sampled});
            transmissionUses.push_back({channels, Access::Sampled});
        }
        frame.add(FramePass{plan.responses ? std::string("slab reflection pass") : fmt::format("transmission pass {}", p),
                            plan.responses ? fmt::format("transmit.frag, OUTPUT_COUNT {}, REFLECTION, RESPONSES; the slab's "
                                                         "reflection × τ in front of it, added to the responses",
                                                         to.attachments)
                            : viewSplit ? fmt::format("transmit.frag, OUTPUT_COUNT {}; the slabs farthest first, blend "
                                                    "destination × source, + their reflection; then the nearest "
                                                    "slab × what lies in front of it (FRONT)",
                                                    to.attachments)
                                      : fmt::format("transmit.frag, OUTPUT_COUNT {}; farthest first, blend destination × "
                                                    "source (slabs: then + their reflection)",
                                                    to.attachments),
                            std::move(transmissionUses), to.renderPass, to.framebuffer.get(), extent,
                            std::vector<VkClearValue>(to.attachments + 1), [this, p](VkCommandBuffer cmd) {
                                const PassObjects& t = transmissionPasses[p];
                                if (plan.responses)
                                    drawTransparent(cmd, *frameState, p, t.pipelines[1], descriptorSet, VK_NULL_HANDLE,
                                                    TransparentDraws::Slabs);
                                else if (viewSplit)
                                    drawTransparent(cmd, *frameState, p, t.pipelines[0], descriptorSet, t.pipelines[1],
                                                    TransparentDraws::Slabs, t.pipelines[2]);
                                else
                                    drawTransparent(cmd, *frameState, p, t.pipelines[0], descriptorSet, t.pipelines[1]);
                            }});
    }
    // The host reads the cube: from the linear image itself, or from a copy into a host buffer. The
    // response pass's target is the tonemap pass's to read (render/tonemap_pass.cpp borrows it).
    if (plan.mappedReadback) {
        frame.add(FramePass{"host read", "the host maps the linear target", {{targetResource, Access::HostRead}}});
    } else if (copies) {
        frame.add(FramePass{"readback copy", "vkCmdCopyImageToBuffer",
                            {{targetResource, Access::TransferSrc}, {readback, Access::TransferDst}}, VK_NULL_HANDLE,
                            VK_NULL_HANDLE, {}, {}, [this, layers](VkCommandBuffer cmd) {
                                VkBufferImageCopy region{};
                                region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, layers};
                                region.imageExtent = {plan.targetWidth, plan.targetHeight, 1};
                                vkCmdCopyImageToBuffer(cmd, color.handle(), vk::accessLayout(Access::TransferSrc),
                                                       readbackBuffer.handle(), 1, &region);
                            }});
        frame.add(FramePass{"host read", "the host maps the readback buffer", {{readback, Access::HostRead}}});
    }
    frame.derive();
}

void recordSpectralFrame(VkCommandBuffer cmd, const SpectralResources& r, const CameraMatrices& camera, size_t first,
                         size_t end) {
    SpectralFrameState state{camera, {}};
    state.pc.viewProjection = camera.viewProjection;
    state.pc.cameraPosition = glm::vec4(camera.position, camera.perspective ? 1.0f : 0.0f);
    state.pc.cameraForward = glm::vec4(camera.forward, 0.0f);
    r.frameState = &state;
    recordFrame(cmd, r.frame, first, end);
    r.frameState = nullptr;
}

}  // namespace metamer
