// Each pass's render pass and pipelines (SpectralResources::createPasses): the depth pre-pass (or
// the distance pre-pass with transparent objects), the band or response passes with a pipeline per
// material variant, the lobe pass, the transmission passes. Attachments stay in the layouts of
// their uses (vk::attachmentFor): the frame's derived barriers (render/frame_pass.h) make every
// transition, so no render pass here carries a dependency.
// Tests: through render/spectral_pass.h's (every GPU test, validation layers on).
#include "render/spectral_resources.h"

#include "interface.h"
#include "render/spectral_shaders.h"
#include "vk/pipeline.h"
#include "vk/render_pass.h"

#include <algorithm>

namespace metamer {

// attachments == 0: the depth pre-pass (clears and writes depth). Otherwise a colour pass that
// loads the pre-pass's depth and shades only the visible surface (depth test EQUAL), so every
// pixel is shaded once per pass whatever the overdraw — or, clearsDepth, one with its own depth.
VkRenderPass SpectralResources::makeRenderPass(uint32_t attachments, bool clearsDepth, bool bandDepthOutput) {
    using vk::Access;
    vk::RenderPassDesc desc;
    // Cleared once per frame by the frame's clear pass (a transfer), not by the render pass: lavapipe
    // (Mesa 22.3) leaks about a target's size of memory per render-pass clear of array-layer views.
    for (uint32_t i = 0; i < attachments; ++i)
        desc.colors.push_back(vk::attachmentFor(VK_FORMAT_R32G32B32A32_SFLOAT, Access::ColorAttachment, VK_ATTACHMENT_LOAD_OP_LOAD));
    if (bandDepthOutput)  // one layer, not an array view: cleared by the render pass
        desc.colors.push_back(vk::attachmentFor(VK_FORMAT_R32_SFLOAT, Access::ColorAttachment, VK_ATTACHMENT_LOAD_OP_CLEAR));
    // Stored: every later pass loads it.
    desc.depth = vk::attachmentFor(VK_FORMAT_D32_SFLOAT, Access::DepthAttachment,
                                   clearsDepth ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD);
    renderPasses.push_back(vk::sharedRenderPass(
        ctx.objects(),
        fmt::format("spectral.pass attachments={} clearsDepth={} bandDepth={}", attachments, clearsDepth, bandDepthOutput),
        desc));
    return renderPasses.back().get();
}

// attachments == 0: the depth pre-pass pipeline (vertex stage only); writesDepth with attachments:
// a colour pass without a pre-pass.
VkPipeline SpectralResources::makePipeline(const vk::SharedHandle<VkRenderPass>& renderPass, uint32_t attachments,
                                           bool writesDepth, int lobeMode, const Variant& v, bool withoutBands) {
    const gpu::SpectralSpecialization spec{packed.ambient,
                                           packed.directional,
                                           packed.point,
                                           plan.hasSpecular && v.specular,
                                           plan.hasFluorescence && v.fluorescent,
                                           scene.hasTextures() && v.textures,
                                           scene.hasNormalMaps() && v.normalMap,
                                           plan.fluorescenceSpectra,
                                           plan.responses,
                                           packed.hemisphere,
                                           packed.shadowMaps.any(),
                                           lobeMode,
                                           packed.shadowedDirectional,
                                           packed.shadowedPoint,
                                           packed.hemispherePaired,
                                           packed.filteredShadows,
                                           packed.bandLayers,
                                           int32_t(packed.lights.emitters.x),
                                           int32_t(packed.lights.emitters.y),
                                           scene.hasEmitters(),
                                           int32_t(plan.quantity),
                                           packed.filteredShadows ? packed.depthChannels : 0,
                                           packed.filteredShadows ? packed.slabChannels : 0,
                                           int32_t(viewChannelLayers > 0 ? packed.depthChannels : 0),
                                           packed.filteredShadows ? packed.flatSlabs : 0u,
                                           packed.slabLayerRows,
                                           viewSlabChannel,
                                           packed.responseChannels,
                                           packed.responseFirstLayer,
                                           packed.responseEndLayer,
                                           packed.crossingHeader,
                                           packed.crossingNodes};
    const VkSpecializationInfo si = vk::specializationOf(spec);
    bool prePass = attachments == 0;
    // Interreflection's band passes add the indirect light (the INDIRECT programs, a second vertex
    // buffer); the pre-pass, the lobe pass and the response pass do not read it.
    const bool indirect = !packed.indirect.empty() && !prePass && lobeMode != LOBE_WRITE && !plan.responses;
    vk::GraphicsPipelineDesc d;
    d.cullMode = v.cullBackFaces ? VK_CULL_MODE_BACK_BIT : VK_CULL_MODE_NONE;
    d.renderPass = renderPass.get();
    d.layout = pipelineLayout.get();
    d.vertex = indirect ? vertIndirect.get() : vert.get();
    d.fragmentSpecialization = &si;
    spectralVertexInput(d, indirect);
    d.width = plan.targetWidth;
    d.height = plan.targetHeight;
    d.colorAttachments = attachments + (withoutBands ? 1 : 0);
    d.depthTest = true;
    d.cache = ctx.pipelineCache();
    d.depthWrite = writesDepth;
    // Same vertex shader (gl_Position is invariant) → the same depth in every pass.
    d.depthCompare = prePass ? VK_COMPARE_OP_LESS : writesDepth ? VK_COMPARE_OP_LESS_OR_EQUAL : VK_COMPARE_OP_EQUAL;
    // Everything the pipeline depends on is in its key (the render pass and layout are shared, so
    // their handles name their descriptions).
    const std::string key =
        fmt::format("spectral.pipeline attachments={} writesDepth={} cull={} indirect={} withoutBands={} {}x{} pass={} "
                    "layout={} spec={}",
                    attachments, writesDepth, int(d.cullMode), indirect, withoutBands, d.width, d.height,
                    static_cast<void*>(renderPass.get()), static_cast<void*>(pipelineLayout.get()),
                    vk::keyBytes(&spec, sizeof spec));
    pipelines.push_back(ctx.objects().pipeline(
        key,
        [&] {
            VkShaderModule frag = VK_NULL_HANDLE;
            if (!prePass) {
                // THROUGH_FILTERS (spectral.frag): its code is in the FILTERED_RESPONSES builds only.
                const bool throughFilters = spec.responses && (spec.viewChannels > 0 || spec.viewSlabChannel >= 0);
                const SpirvCode fragCode = indirect         ? spectralIndirectFragment(attachments)
                                           : withoutBands   ? spectralResponsesWithoutBandsFragment(attachments)
                                           : throughFilters ? spectralFilteredResponsesFragment(attachments)
                                                            : spectralFragment(attachments);
                frag = vk::createShaderModule(ctx.device(), fragCode.code, fragCode.bytes);
            }
            const vk::OwnedShaderModule fragModule(ctx.device(), frag);  // the pipeline keeps what it needs
            d.fragment = frag;
            return vk::createGraphicsPipeline(ctx.device(), d);
        },
        {renderPass, pipelineLayout}));
    return pipelines.back().get();
}

// Each material's variant, from what its packed block says (the same flags the shader tests), and
// its culled one when it has closed meshes.
void SpectralResources::classifyDraws() {
    auto index = [&](const Variant& v) {
        const auto found = std::find(variants.begin(), variants.end(), v);
        if (found != variants.end()) return uint32_t(found - variants.begin());
        variants.push_back(v);
        return uint32_t(variants.size() - 1);
    };
    const size_t materials = packed.materials.size() / std::max<size_t>(1, size_t(plan.passes));
    for (size_t m = 0; m < materials; ++m) {
        const gpu::GpuMaterialBlock& b = packed.materials[m];  // pass 0's: the flags are the same in every pass
        const uint32_t on = b.switches.x;
        Variant v{(on & MATERIAL_SPECULAR) != 0, (on & MATERIAL_FLUORESCENT) != 0,
                  (on & (MATERIAL_DIFFUSE_TEXTURE | MATERIAL_SPECULAR_TEXTURE | MATERIAL_NORMAL_TEXTURE)) != 0,
                  (on & MATERIAL_NORMAL_TEXTURE) != 0, false};
        materialVariant.push_back(index(v));
        materialCulledVariant.push_back(-1);
        const bool closedMesh = std::any_of(packed.draws.begin(), packed.draws.end(), [&](const PackedDraw& d) {
            return (d.closed || d.alwaysCull) && d.material == m;
        });
        if (closedMesh) {
            v.cullBackFaces = true;
            materialCulledVariant.back() = int32_t(index(v));
        }
    }
    if (variants.empty()) variants.push_back({});
}

std::vector<VkPipeline> SpectralResources::makePipelines(const vk::SharedHandle<VkRenderPass>& renderPass,
                                                         uint32_t attachments, bool writesDepth, int lobeMode,
                                                         bool withoutBands) {
    std::vector<VkPipeline> out;
    for (const Variant& v : variants)
        out.push_back(makePipeline(renderPass, attachments, writesDepth, lobeMode, v, withoutBands));
    return out;
}

void SpectralResources::createPasses() {
    classifyDraws();
    // The band passes shade each pixel once behind a depth pre-pass. The response pass has one
    // pass, and the pre-pass pays there only where shading is costly enough for overdraw to
    // matter: textured materials (texel fetches per fragment). Measured at 1024²: textured.json
    // 30.9 → 27.9 ms; spheres.json (the environment lookup, back faces culled) 33.4 → 34.3 and
    // imaging-systems.json 25.2 → 24.1, noise either way (docs/performance.md). Transparent objects
    // need it for the opaque distance their channel pass measures from.
    hasDepthPrePass = !plan.responses || scene.hasTextures() || hasTransmission;
    if (hasTransmission) {
        createDistancePrePass();
    } else if (hasDepthPrePass) {
        PassObjects& pre = depthPrePass;
        pre.renderPass = makeRenderPass(0, true);
        Variant culled;
        culled.cullBackFaces = true;
        pre.pipelines = {makePipeline(renderPasses.back(), 0, true, LOBE_COMPUTE, {}),
                         makePipeline(renderPasses.back(), 0, true, LOBE_COMPUTE, culled)};
        pre.framebuffer =
            vk::createFramebuffer(ctx.device(), pre.renderPass, {depth.layerView(0)}, plan.targetWidth, plan.targetHeight);
    }
    // One render pass + pipeline per distinct attachment count (at most two: 8 and the rest).
    VkRenderPass rpFull = VK_NULL_HANDLE, rpLast = VK_NULL_HANDLE;
    std::vector<VkPipeline> plFull, plLast;
    for (int p = 0; p < plan.passes; ++p) {
        PassObjects po;
        po.firstLayer = uint32_t(p * MAX_OUTPUTS);
        po.attachments = std::min<uint32_t>(MAX_OUTPUTS, uint32_t(plan.layers) - po.firstLayer);
        bool full = po.attachments == MAX_OUTPUTS;
        VkRenderPass& rp = full ? rpFull : rpLast;
        std::vector<VkPipeline>& pl = full ? plFull : plLast;
        if (rp == VK_NULL_HANDLE) {
            rp = makeRenderPass(po.attachments, !hasDepthPrePass);
            pl = makePipelines(renderPasses.back(), po.attachments, !hasDepthPrePass, hasLobePass ? LOBE_READ : LOBE_COMPUTE);
        }
        po.renderPass = rp;
        po.pipelines = pl;
        std::vector<VkImageView> views;
        for (uint32_t i = 0; i < po.attachments; ++i) views.push_back(color.layerView(po.firstLayer + i));
        views.push_back(depth.layerView(0));
        po.framebuffer = vk::createFramebuffer(ctx.device(), rp, views, plan.targetWidth, plan.targetHeight);
        passes.push_back(std::move(po));
    }
    if (bandSplit) {
        // The response pass's first draw (every pixel, no per-band sums, the band pass depth out)
        // and the framebuffer of its second (the pixels that need them, by their depth).
        PassObjects& first = responsesWithoutBands;
        const PassObjects& response = passes.at(0);
        first.attachments = response.attachments;
        first.renderPass = makeRenderPass(first.attachments, false, true);
        first.pipelines = makePipelines(renderPasses.back(), first.attachments, false, LOBE_COMPUTE, true);
        std::vector<VkImageView> views;
        for (uint32_t i = 0; i < first.attachments; ++i) views.push_back(color.layerView(i));
        std::vector<VkImageView> second = views;
        views.push_back(bandPassDepthColor.layerView(0));
        views.push_back(depth.layerView(0));
        first.framebuffer = vk::createFramebuffer(ctx.device(), first.renderPass, views, plan.targetWidth, plan.targetHeight);
        second.push_back(bandDepth.layerView(0));
        bandFramebuffer = vk::createFramebuffer(ctx.device(), response.renderPass, second, plan.targetWidth, plan.targetHeight);
    }
    if (hasLobePass) createLobePass();
    if (viewChannelLayers > 0) createViewChannelPass();
    if (hasTransmission && (viewChannelLayers == 0 || viewSplit)) createTransmissionPasses();
    declareFrame();
}

// A render pass of `attachments` RGBA32F layers of optical-depth channels, cleared to 0 (nothing crossed).
VkRenderPass SpectralResources::channelRenderPass(uint32_t attachments) {
    vk::RenderPassDesc desc;
    for (uint32_t i = 0; i < attachments; ++i)
        desc.colors.push_back(
            vk::attachmentFor(VK_FORMAT_R32G32B32A32_SFLOAT, vk::Access::ColorAttachment, VK_ATTACHMENT_LOAD_OP_CLEAR));
    renderPasses.push_back(
        vk::sharedRenderPass(ctx.objects(), fmt::format("spectral.channels attachments={}", attachments), desc));
    return renderPasses.back().get();
}

// transmit.frag writing optical-depth channels FIRST_CHANNEL … into `attachments` layers, added (the
// coloured shadows' maps at `size`², the camera's channel pass at the target's size, `split` by the
// nearest slab).
VkPipeline SpectralResources::makeChannelPipeline(VkRenderPass renderPass, uint32_t attachments, uint32_t size,
                                                  int32_t firstChannel, bool split) {
    const SpirvCode code = transmitFragment(attachments);
    vk::GraphicsPipelineDesc pd = transparentPipelineDesc(renderPass, attachments, size);
    pd.multiplyBlend = false;
    pd.addBlend = true;  // the channels add
    gpu::TransmitSpecialization spec{};
    spec.channelOutput = VK_TRUE;
    spec.firstChannel = firstChannel;
    spec.split = split ? VK_TRUE : VK_FALSE;
    const VkSpecializationInfo si = vk::specializationOf(spec);
    return makeOwnPipeline(fmt::format("spectral.channels attachments={} {}x{} pass={} layout={} spec={}", attachments,
                                       pd.width, pd.height, static_cast<void*>(renderPass),
                                       static_cast<void*>(pipelineLayout.get()), vk::keyBytes(&spec, sizeof spec)),
                           pd, code.code, code.bytes, &si);
}

// The camera's channel pass (scenes whose transparent objects are sheets and media): after the
// depth pre-pass, every transparent object once, adding its optical-depth channels (transmit.frag,
// CHANNEL_OUTPUT) in front of the opaque surface, for the band passes to turn into τ per band.
void SpectralResources::createViewChannelPass() {
    viewChannelPass.renderPass = channelRenderPass(viewChannelLayers);
    viewChannelPass.attachments = viewChannelLayers;
    viewChannelPass.pipelines = {makeChannelPipeline(viewChannelPass.renderPass, viewChannelLayers, 0, 0, viewSplit)};
    std::vector<VkImageView> views;
    for (uint32_t i = 0; i < viewChannelLayers; ++i) views.push_back(viewChannels.layerView(i));
    viewChannelPass.framebuffer =
        vk::createFramebuffer(ctx.device(), viewChannelPass.renderPass, views, plan.targetWidth, plan.targetHeight);
    if (!viewSplit) return;
    // The slab distance pass: the nearest slab's distance, by its own depth — the depth pre-pass's
    // render pass and its pipeline that keeps back faces (LESS), into images of its own.
    slabDistancePass.renderPass = depthPrePass.renderPass;
    slabDistancePass.attachments = 1;
    slabDistancePass.pipelines = {depthPrePass.pipelines[0]};
    slabDistancePass.framebuffer = vk::createFramebuffer(ctx.device(), slabDistancePass.renderPass,
                                                         {slabDistance.layerView(0), slabDepth.layerView(0)},
                                                         plan.targetWidth, plan.targetHeight);
}

// The depth pre-pass of a scene with transparent objects: it also writes the nearest opaque
// surface's distance (opaque_distance.frag) into an R32F image, which the transmission passes
// sample. Pipelines: back faces kept, and culled.
vk::RenderPassDesc SpectralResources::distancePrePassDesc() const {
    vk::RenderPassDesc desc;
    desc.colors.push_back(vk::attachmentFor(VK_FORMAT_R32_SFLOAT, vk::Access::ColorAttachment, VK_ATTACHMENT_LOAD_OP_CLEAR));
    desc.depth = vk::attachmentFor(VK_FORMAT_D32_SFLOAT, vk::Access::DepthAttachment, VK_ATTACHMENT_LOAD_OP_CLEAR);
    return desc;
}

void SpectralResources::createDistancePrePass() {
    const vk::RenderPassDesc desc = distancePrePassDesc();
    renderPasses.push_back(vk::sharedRenderPass(
        ctx.objects(), fmt::format("spectral.distance pre-pass {}x{}", plan.targetWidth, plan.targetHeight), desc));
    PassObjects& pre = depthPrePass;
    pre.renderPass = renderPasses.back().get();
    pre.attachments = 1;
    for (bool cull : {false, true}) {
        vk::GraphicsPipelineDesc d = transparentPipelineDesc(pre.renderPass, 1);
        d.depthTest = d.depthWrite = true;
        d.depthCompare = VK_COMPARE_OP_LESS;
        d.multiplyBlend = false;
        d.cullMode = cull ? VK_CULL_MODE_BACK_BIT : VK_CULL_MODE_NONE;
        pre.pipelines.push_back(makeOwnPipeline(
            fmt::format("spectral.distance pre-pass cull={} {}x{} pass={} layout={}", cull, d.width, d.height,
                        static_cast<void*>(pre.renderPass), static_cast<void*>(pipelineLayout.get())),
            d, opaqueDistanceFragment().code, opaqueDistanceFragment().bytes));
    }
    pre.framebuffer = vk::createFramebuffer(ctx.device(), pre.renderPass, {opaqueDistance.layerView(0), depth.layerView(0)},
                                            plan.targetWidth, plan.targetHeight);
}

// What the distance pre-pass's and the transmission passes' pipelines share: spectral.vert, the
// spectral layout, no depth test, colours blended destination × source.
vk::GraphicsPipelineDesc SpectralResources::transparentPipelineDesc(VkRenderPass renderPass, uint32_t attachments,
                                                                   uint32_t size) const {
    vk::GraphicsPipelineDesc d;
    d.renderPass = renderPass;
    d.layout = pipelineLayout.get();
    d.vertex = vert.get();
    spectralVertexInput(d);
    d.width = size ? size : plan.targetWidth;
    d.height = size ? size : plan.targetHeight;
    d.colorAttachments = attachments;
    d.multiplyBlend = true;
    d.cache = ctx.pipelineCache();
    return d;
}

// A pipeline of `d` with the fragment shader `code`, shared through the device's cache under `key`.
VkPipeline SpectralResources::makeOwnPipeline(const std::string& key, vk::GraphicsPipelineDesc d, const uint32_t* code,
                                              size_t bytes, const VkSpecializationInfo* specialization) {
    d.fragmentSpecialization = specialization;
    pipelines.push_back(ctx.objects().pipeline(
        key,
        [&] {
            const vk::OwnedShaderModule frag(ctx.device(), vk::createShaderModule(ctx.device(), code, bytes));
            d.fragment = frag.get();
            return vk::createGraphicsPipeline(ctx.device(), d);
        },
        {renderPasses.back(), pipelineLayout}));
    return pipelines.back().get();
}

// After band pass p, on its layers: colours loaded and blended (destination × source), the opaque
// distance sampled by transmit.frag; no depth.
void SpectralResources::createTransmissionPasses() {
    VkRenderPass rpFull = VK_NULL_HANDLE, rpLast = VK_NULL_HANDLE;
    VkPipeline plFull = VK_NULL_HANDLE, plLast = VK_NULL_HANDLE, reflectFull = VK_NULL_HANDLE, reflectLast = VK_NULL_HANDLE;
    VkPipeline frontFull = VK_NULL_HANDLE, frontLast = VK_NULL_HANDLE;
    // With the channel pass split by the nearest slab: that slab's second draw multiplies by τ of
    // what lies in front of it (blend destination × source).
    gpu::TransmitSpecialization frontSpec{};
    frontSpec.front = VK_TRUE;
    frontSpec.viewChannels = packed.depthChannels;
    frontSpec.bandLayers = packed.bandLayers;
    const VkSpecializationInfo frontInfo = vk::specializationOf(frontSpec);
    const bool slabs = std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.isSlab(); });
    // The slabs' reflection draws add R·(ambient and hemisphere lights in the mirror direction).
    gpu::TransmitSpecialization reflection{};
    reflection.reflection = VK_TRUE;
    reflection.ambientCount = packed.ambient;
    reflection.hemisphereFirst = packed.ambient + packed.directional + packed.point;
    reflection.hemisphereCount = packed.hemisphere;
    reflection.bandLayers = 1;  // the shader's default: read by FRONT only
    if (plan.responses) {
        // The response pass's slab reflection: every band layer, τ of what lies in front of it.
        reflection.responses = VK_TRUE;
        reflection.viewChannels = packed.depthChannels;
        reflection.bandLayers = packed.bandLayers;
        reflection.responseChannels = packed.responseChannels;
        reflection.responseFirstLayer = packed.responseFirstLayer;
        reflection.responseEndLayer = packed.responseEndLayer;
    }
    const VkSpecializationInfo reflectionInfo = vk::specializationOf(reflection);
    for (const PassObjects& band : passes) {
        PassObjects po;
        po.firstLayer = band.firstLayer;
        po.attachments = band.attachments;
        const bool full = po.attachments == MAX_OUTPUTS;
        VkRenderPass& rp = full ? rpFull : rpLast;
        VkPipeline& pl = full ? plFull : plLast;
        VkPipeline& reflect = full ? reflectFull : reflectLast;
        VkPipeline& front = full ? frontFull : frontLast;
        if (rp == VK_NULL_HANDLE) {
            vk::RenderPassDesc desc;
            for (uint32_t i = 0; i < po.attachments; ++i)
                desc.colors.push_back(
                    vk::attachmentFor(VK_FORMAT_R32G32B32A32_SFLOAT, vk::Access::ColorAttachment, VK_ATTACHMENT_LOAD_OP_LOAD));
            renderPasses.push_back(vk::sharedRenderPass(
                ctx.objects(), fmt::format("spectral.transmission attachments={}", po.attachments), desc));
            rp = renderPasses.back().get();
            const SpirvCode code = transmitFragment(po.attachments);
            pl = makeOwnPipeline(fmt::format("spectral.transmission attachments={} {}x{} pass={} layout={}", po.attachments,
                                             plan.targetWidth, plan.targetHeight, static_cast<void*>(rp),
                                             static_cast<void*>(pipelineLayout.get())),
                                 transparentPipelineDesc(rp, po.attachments), code.code, code.bytes);
            if (slabs) {
                vk::GraphicsPipelineDesc rd = transparentPipelineDesc(rp, po.attachments);
                rd.multiplyBlend = false;
                rd.addBlend = true;
                reflect = makeOwnPipeline(
                    fmt::format("spectral.reflection attachments={} {}x{} pass={} layout={} spec={}", po.attachments,
                                plan.targetWidth, plan.targetHeight, static_cast<void*>(rp),
                                static_cast<void*>(pipelineLayout.get()), vk::keyBytes(&reflection, sizeof reflection)),
                    rd, code.code, code.bytes, &reflectionInfo);
            }
            if (viewSplit && !plan.responses)
                front = makeOwnPipeline(
                    fmt::format("spectral.slab front attachments={} {}x{} pass={} layout={} spec={}", po.attachments,
                                plan.targetWidth, plan.targetHeight, static_cast<void*>(rp),
                                static_cast<void*>(pipelineLayout.get()), vk::keyBytes(&frontSpec, sizeof frontSpec)),
                    transparentPipelineDesc(rp, po.attachments), code.code, code.bytes, &frontInfo);
        }
        po.renderPass = rp;
        po.pipelines = {pl, reflect, front};
        std::vector<VkImageView> views;
        for (uint32_t i = 0; i < po.attachments; ++i) views.push_back(color.layerView(po.firstLayer + i));
        po.framebuffer = vk::createFramebuffer(ctx.device(), rp, views, plan.targetWidth, plan.targetHeight);
        transmissionPasses.push_back(std::move(po));
    }
}

// The lobe pass: one RGBA32F attachment that the band passes sample, the pre-pass's depth loaded
// and tested EQUAL (each visible surface shaded once, as in the band passes).
void SpectralResources::createLobePass() {
    vk::RenderPassDesc desc;
    // DONT_CARE: read only where a surface is drawn.
    desc.colors.push_back(
        vk::attachmentFor(VK_FORMAT_R32G32B32A32_SFLOAT, vk::Access::ColorAttachment, VK_ATTACHMENT_LOAD_OP_DONT_CARE));
    desc.depth = vk::attachmentFor(VK_FORMAT_D32_SFLOAT, vk::Access::DepthAttachment, VK_ATTACHMENT_LOAD_OP_LOAD);
    renderPasses.push_back(vk::sharedRenderPass(
        ctx.objects(), fmt::format("spectral.lobe pass {}x{}", plan.targetWidth, plan.targetHeight), desc));
    lobePass.renderPass = renderPasses.back().get();
    lobePass.attachments = 1;
    lobePass.pipelines = makePipelines(renderPasses.back(), 1, false, LOBE_WRITE);
    lobePass.framebuffer = vk::createFramebuffer(ctx.device(), lobePass.renderPass,
                                                 {lobeWeights.layerView(0), depth.layerView(0)}, plan.targetWidth,
                                                 plan.targetHeight);
}

}  // namespace metamer
