#include "render/spectral_resources.h"

#include "core/timing.h"
#include "interface.h"
#include "lobe_lookup.h"
#include "render/transmittance_map_cost.h"

#include <algorithm>
#include <cstddef>

namespace metamer {

namespace {

// A texel-buffer view of the whole of `buffer` in `format`.
vk::OwnedBufferView texelBufferView(VkDevice device, const vk::Buffer& buffer, VkFormat format) {
    VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
    info.buffer = buffer.handle();
    info.format = format;
    info.range = VK_WHOLE_SIZE;
    VkBufferView view = VK_NULL_HANDLE;
    VK_CHECK(vkCreateBufferView(device, &info, nullptr, &view));
    return vk::OwnedBufferView(device, view);
}


}  // namespace


SpectralResources::SpectralResources(vk::Context& c, const Scene& s, const SceneOnGrid& spectra,
                                     const PackedScene& p, SpectralPassPlan& pl, const SpectralPassOptions& options)
    : ctx(c), scene(s), packed(p), plan(pl) {
    // The ground-truth maps are of the opaque surface seen: nothing transparent is drawn for them.
    hasTransmission = plan.quantity == SurfaceQuantity::Radiance &&
                      std::any_of(packed.draws.begin(), packed.draws.end(), [](const PackedDraw& d) { return d.transparent; });
    // The camera's channel pass: for the sheets and media (a set of channels), and with slabs in the
    // scene too, two sets (behind and in front of the nearest slab), within one pass's attachments.
    const uint32_t channelLayers = uint32_t(packed.depthChannels + 3) / 4;
    const bool slabs = packed.slabChannels > 0;
    if (hasTransmission && channelLayers >= 1 && channelLayers * (slabs ? 2 : 1) <= MAX_OUTPUTS) {
        viewChannelLayers = channelLayers * (slabs ? 2 : 1);
        viewSplit = slabs;
    }
    // The response pass carries sheets and media (their τ inside its sums) and one planar slab
    // (Scene::transparencyInResponses): a slab alone still has the split channel pass (empty sets),
    // for the slab distance pass beside it.
    if (hasTransmission && packed.responses) {
        if (slabs && channelLayers == 0) {
            viewChannelLayers = 2;
            viewSplit = true;
        }
        if (viewChannelLayers == 0 || (viewSplit && !scene.transparencyInResponses()))
            failRuntime("the response pass shows sheets and media, at most {} materials, and one planar slab: "
                        "render bands (render/display_frame.cpp does)", 4 * MAX_OUTPUTS);
        if (viewSplit)
            for (const PackedDraw& d : packed.draws)
                if ((packed.materials[d.material].switches.x & MATERIAL_SLAB) != 0u) {
                    viewSlabChannel = int32_t(packed.materials[d.material].params.w);
                    break;
                }
        bandSplit = true;
    }
    // The coloured shadows' cost grows with the transparent area the lights see × the channels'
    // layers: said when it is long, refused when it would take hours, before anything is drawn.
    if (packed.filteredShadows) {
        transmittanceCost = transmittanceMapCost(packed, TRANSMITTANCE_MAP_SIZE);
        const Where where{scene.file.string(), "lights"};
        if (transmittanceCost.seconds > kMaxTransmittanceMapSeconds)
            failInput(where, "coloured shadows: {}, more than the {:g} s a scene's transmittance maps may take; cast "
                      "shadows from fewer lights (\"shadows\": false), make the transparent objects fewer or smaller "
                      "in the lights' view (docs/numerics.md, \"Scale of transparent scenes\")",
                      describe(transmittanceCost), kMaxTransmittanceMapSeconds);
        if (transmittanceCost.seconds > kSlowTransmittanceMapSeconds)
            warn(where, "coloured shadows: " + describe(transmittanceCost) + " (drawn once per scene)");
    }
    createBuffers();
    createShadowMaps();
    // The response pass reads response textures (render/spectral_packing.h) instead of spectral ones.
    std::vector<const TextureOnGrid*> list;
    if (packed.responses) {
        materialTextures = packed.responseTextureSlots;
        for (const TextureOnGrid& t : packed.responseTextures) list.push_back(&t);
    } else {
        for (const MaterialOnGrid& mat : spectra.materials)
            materialTextures.push_back({mat.diffuseTexture, mat.specularTexture, mat.normalTexture});
        for (const TextureOnGrid& t : spectra.textures) list.push_back(&t);
    }
    createTextures(list);
    // Nobody reads the response pass's target but the tonemap pass: an OPTIMAL image, no copy.
    createTargets(packed.responses ? Readback::Copy : options.readback, options.sampled, pl);
    // The lobe pass pays off with several band passes; the response pass has one.
    hasLobePass = !packed.responses && plan.passes > 1 && plan.hasSpecular && packed.hemisphere >= 1 &&
                  packed.hemisphere <= MAX_LOBE_LIGHTS;
    if (hasLobePass) {
        vk::ImageDesc ld;
        ld.width = plan.targetWidth;
        ld.height = plan.targetHeight;
        ld.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
        ld.name = "lobe weights";
        lobeWeights = vk::Image(ctx, ld);
    }
    if (packed.filteredShadows) createShadowTransmittanceImages();
    createLayouts();
    createPasses();
    if (packed.filteredShadows) drawShadowTransmittance();
}

VkDeviceSize SpectralResources::aligned(VkDeviceSize size) const {
    VkDeviceSize a = std::max<VkDeviceSize>(16, ctx.properties().limits.minUniformBufferOffsetAlignment);
    return (size + a - 1) / a * a;
}

// Copies `count` records of `size` bytes into a uniform buffer with records `stride` apart.
vk::Buffer SpectralResources::uniforms(const void* data, size_t size, size_t count, VkDeviceSize stride,
                                       const char* name) {
    vk::Buffer b(ctx, std::max<VkDeviceSize>(stride * std::max<size_t>(count, 1), 16),
                 VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, name);
    for (size_t i = 0; i < count; ++i) b.upload(static_cast<const char*>(data) + i * size, size, i * stride);
    return b;
}

void SpectralResources::createBuffers() {
    if (!packed.vertices.empty()) {
        const size_t bytes = packed.vertices.size() * sizeof(gpu::SpectralVertex);
        vertexBuffer = vk::Buffer(ctx, bytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, "vertices");
        vertexBuffer.upload(packed.vertices.data(), bytes);
        indexBuffer = vk::Buffer(ctx, packed.indices.size() * 4, VK_BUFFER_USAGE_INDEX_BUFFER_BIT, "indices");
        indexBuffer.upload(packed.indices.data(), packed.indices.size() * 4);
    }
    if (!packed.indirect.empty()) {
        const VkDeviceSize bytes = packed.indirect.size() * sizeof(glm::vec4);
        indirectBuffer = vk::Buffer(ctx, bytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, "indirect light");
        indirectBuffer.upload(packed.indirect.data(), bytes);
        indirectPassBytes = bytes / VkDeviceSize(std::max(1, plan.passes));
    }
    lightBuffer = uniforms(&packed.lights, sizeof(gpu::GpuLightBlock), 1, sizeof(gpu::GpuLightBlock), "lights");
    lightSpectraStride = aligned(sizeof(gpu::GpuLightSpectraBlock));
    lightSpectraBuffer = uniforms(packed.lightSpectra.data(), sizeof(gpu::GpuLightSpectraBlock),
                                  packed.lightSpectra.size(), lightSpectraStride, "light spectra");
    materialStride = aligned(sizeof(gpu::GpuMaterialBlock));
    materialBuffer = uniforms(packed.materials.data(), sizeof(gpu::GpuMaterialBlock), packed.materials.size(),
                              materialStride, "materials");
    // Fluorescence records are sized to the scene's lights, but bound with the whole block's
    // range: the buffer extends past the last record so that range stays inside it.
    const size_t recordBytes = size_t(packed.lightSlots) * MAX_OUTPUTS * sizeof(glm::vec4);
    const size_t records = packed.fluorescence.size() / (size_t(packed.lightSlots) * MAX_OUTPUTS);
    fluorescenceStride = aligned(recordBytes);
    fluorescenceBuffer = vk::Buffer(ctx, (records - 1) * fluorescenceStride + sizeof(gpu::GpuFluorescenceBlock),
                                    VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, "fluorescence");
    std::vector<char> zeros(sizeof(gpu::GpuFluorescenceBlock) - recordBytes, 0);
    for (size_t r = 0; r < records; ++r)
        fluorescenceBuffer.upload(&packed.fluorescence[r * packed.lightSlots * MAX_OUTPUTS], recordBytes,
                                  r * fluorescenceStride);
    if (!zeros.empty())  // the tail past the last record: never read, but defined
        fluorescenceBuffer.upload(zeros.data(), zeros.size(), (records - 1) * fluorescenceStride + recordBytes);
    // The band passes bind one zero block (the shader declares it, reads it only as the response pass).
    responseStride = aligned(sizeof(gpu::GpuResponseBlock));
    const gpu::GpuResponseBlock none{};
    responseBuffer = packed.responses ? uniforms(packed.responseBlocks.data(), sizeof(gpu::GpuResponseBlock),
                                                 packed.responseBlocks.size(), responseStride, "responses")
                                      : uniforms(&none, sizeof none, 1, responseStride, "responses (unused)");
    // The lobe tables (one entry when the scene has none: a binding must have a buffer), read as a
    // texel buffer: lavapipe gathers texel fetches in SIMD, where a storage buffer indexed per
    // fragment is loaded lane by lane (measured: the lookup 2 ms faster in 10 at 512²).
    const size_t lobeEntries = std::max<size_t>(1, packed.lobeTables.size());
    const VkDeviceSize lobeBytes = lobeEntries * sizeof(glm::uvec4);
    if (lobeEntries > ctx.properties().limits.maxTexelBufferElements)
        failInput(Where{scene.file.string(), "materials", 0},
                  "the specular materials' {} gloss values under hemisphere lights need {:.0f} MiB of lobe tables "
                  "(one per gloss value, docs/physics.md \"Hemisphere lights\"); this device reads at most {:.0f} MiB: "
                  "use fewer distinct gloss values",
                  packed.lobeTables.size() / LOBE_TABLE_UVEC4, lobeBytes / 1048576.0,
                  ctx.properties().limits.maxTexelBufferElements * sizeof(glm::uvec4) / 1048576.0);
    lobeTableBuffer = vk::Buffer(ctx, lobeBytes, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT, "lobe tables");
    const glm::uvec4 zero(0u);
    lobeTableBuffer.upload(packed.lobeTables.empty() ? &zero : packed.lobeTables.data(), lobeBytes);
    lobeTableView = texelBufferView(ctx.device(), lobeTableBuffer, VK_FORMAT_R32G32B32A32_UINT);
    // The excitation integrands (one zero entry when there are none), a texel buffer as the tables.
    const VkDeviceSize excitationBytes = packed.shadowExcitation.size() * sizeof(glm::vec4);
    if (packed.shadowExcitation.size() > ctx.properties().limits.maxTexelBufferElements)
        failInput(Where{scene.file.string(), "materials", 0},
                  "the fluorescent materials' excitation under coloured shadows needs {} texels; this device reads at "
                  "most {}",
                  packed.shadowExcitation.size(), ctx.properties().limits.maxTexelBufferElements);
    shadowExcitationBuffer = vk::Buffer(ctx, excitationBytes, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT, "shadow excitation");
    shadowExcitationBuffer.upload(packed.shadowExcitation.data(), excitationBytes);
    shadowExcitationView = texelBufferView(ctx.device(), shadowExcitationBuffer, VK_FORMAT_R32G32B32A32_SFLOAT);
    // The optical-depth channels' spectra (one zero entry when there are none): at most
    // MAX_DEPTH_CHANNELS × BAND_LAYERS texels, within every device's limit; in the response pass
    // through transparent objects, the materials' response spectra after them (DisplayFrame draws
    // bands where they would not fit).
    if (packed.depthSpectra.size() > ctx.properties().limits.maxTexelBufferElements)
        failRuntime("the optical-depth and response spectra need {} texels; this device reads at most {}",
                    packed.depthSpectra.size(), ctx.properties().limits.maxTexelBufferElements);
    const VkDeviceSize depthBytes = packed.depthSpectra.size() * sizeof(glm::vec4);
    depthSpectraBuffer = vk::Buffer(ctx, depthBytes, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT, "optical-depth spectra");
    depthSpectraBuffer.upload(packed.depthSpectra.data(), depthBytes);
    depthSpectraView = texelBufferView(ctx.device(), depthSpectraBuffer, VK_FORMAT_R32G32B32A32_SFLOAT);
}

// Each texture as an RGBA32F 2D-array image, 4 channels per layer (zero-padded), copied from a
// staging buffer; the last image is a 1×1 placeholder for untextured slots.
void SpectralResources::createTextures(std::vector<const TextureOnGrid*> list) {
    TextureOnGrid placeholder;
    placeholder.width = placeholder.height = 1;
    placeholder.channels = 4;
    placeholder.data.assign(4, 0.0f);
    list.push_back(&placeholder);
    const auto& limits = ctx.properties().limits;
    for (const TextureOnGrid* t : list) {
        uint32_t layers = uint32_t((t->channels + 3) / 4);
        if (uint32_t(t->width) > limits.maxImageDimension2D || uint32_t(t->height) > limits.maxImageDimension2D ||
            layers > limits.maxImageArrayLayers)
            failInput(Where{scene.file.string(), "materials"},
                      "a {}×{} texture with {} layers exceeds the device's limits ({} texels per side, {} layers)",
                      t->width, t->height, layers, limits.maxImageDimension2D, limits.maxImageArrayLayers);
        vk::ImageDesc d;
        d.width = uint32_t(t->width);
        d.height = uint32_t(t->height);
        d.layers = layers;
        d.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        d.name = "texture";
        vk::Image image(ctx, d);
        // Layer-major staging: layer l holds channels 4l..4l+3 of every texel.
        const size_t texels = size_t(t->width) * t->height;
        vk::Buffer staging(ctx, texels * layers * 16, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, "texture staging");
        float* out = static_cast<float*>(staging.mapped());
        for (uint32_t l = 0; l < layers; ++l)
            for (size_t p = 0; p < texels; ++p)
                for (int c = 0; c < 4; ++c) {
                    int ch = int(l) * 4 + c;
                    out[(l * texels + p) * 4 + c] = ch < t->channels ? t->data[p * t->channels + ch] : 0.0f;
                }
        staging.flush();
        // One pass: the copy, the image new before it and sampled after it (render/frame_pass.h).
        Frame upload;
        const size_t target = upload.add(FrameResource::madeFor("texture", image.handle(), layers, {vk::Access::Sampled}));
        // Host writes before the submission are visible to it: the staging buffer enters settled.
        const size_t source = upload.add(FrameResource::settled("texture staging", staging.handle(), vk::Access::TransferSrc));
        upload.add(FramePass{"texture upload", "vkCmdCopyBufferToImage",
                             {{target, vk::Access::TransferDst, 0, kAllLayers, false}, {source, vk::Access::TransferSrc}},
                             VK_NULL_HANDLE, VK_NULL_HANDLE, {}, {}, [&](VkCommandBuffer cmd) {
                                 VkBufferImageCopy region{};
                                 region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, layers};
                                 region.imageExtent = {d.width, d.height, 1};
                                 vkCmdCopyBufferToImage(cmd, staging.handle(), image.handle(),
                                                        vk::accessLayout(vk::Access::TransferDst), 1, &region);
                             }});
        upload.derive();
        ctx.submitAndWait([&](VkCommandBuffer cmd) { recordFrame(cmd, upload); });
        textures.push_back(std::move(image));
    }
}

void SpectralResources::createTargets(Readback mode, bool sampled, SpectralPassPlan& plan) {
    uint32_t w = plan.targetWidth, h = plan.targetHeight, layers = uint32_t(plan.layers);
    VkImageUsageFlags sampledBit = sampled ? VK_IMAGE_USAGE_SAMPLED_BIT : 0;
    bool tryMap = mode != Readback::Copy &&
                  vk::supportsLinearRenderTarget(ctx, VK_FORMAT_R32G32B32A32_SFLOAT, w, h, layers, sampled);
    if (mode == Readback::Map && !tryMap)
        failRuntime("--readback map: this device cannot render into a linear host-visible {}×{}×{} image",
                    w, h, layers);
    vk::ImageDesc cd;
    cd.width = w;
    cd.height = h;
    cd.layers = layers;
    cd.name = "spectral target";
    if (tryMap) {
        cd.tiling = VK_IMAGE_TILING_LINEAR;
        cd.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | sampledBit;
        cd.hostVisible = true;
        try {
            color = vk::Image(ctx, cd);
            plan.mappedReadback = true;
        } catch (const Error&) {
            if (mode == Readback::Map) throw;
            tryMap = false;  // e.g. no host-visible memory type fits this image: copy instead
        }
    }
    if (!tryMap) {
        cd.tiling = VK_IMAGE_TILING_OPTIMAL;
        cd.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                   VK_IMAGE_USAGE_TRANSFER_DST_BIT | sampledBit;
        cd.hostVisible = false;
        color = vk::Image(ctx, cd);
        plan.mappedReadback = false;
        if (!plan.responses)
            readbackBuffer = vk::Buffer(ctx, plan.targetBytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, "readback");
    }
    // The frame's other images, the target's size: depth, and with transparent objects the opaque
    // surfaces' distance, the view channels, the nearest slab's distance and its depth.
    auto image = [&](VkFormat format, uint32_t imageLayers, VkImageUsageFlags usage, const char* name) {
        vk::ImageDesc d;
        d.format = format;
        d.width = w;
        d.height = h;
        d.layers = imageLayers;
        d.usage = usage;
        d.name = name;
        return vk::Image(ctx, d);
    };
    constexpr VkImageUsageFlags sampledAttachment = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    depth = image(VK_FORMAT_D32_SFLOAT, 1, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, "depth");
    if (hasTransmission) opaqueDistance = image(VK_FORMAT_R32_SFLOAT, 1, sampledAttachment, "opaque distance");
    if (viewChannelLayers > 0)
        viewChannels = image(VK_FORMAT_R32G32B32A32_SFLOAT, viewChannelLayers, sampledAttachment, "view channels");
    if (viewSplit) {
        slabDistance = image(VK_FORMAT_R32_SFLOAT, 1, sampledAttachment, "slab distance");
        slabDepth = image(VK_FORMAT_D32_SFLOAT, 1, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, "slab depth");
    }
    if (bandSplit) {
        bandPassDepthColor = image(VK_FORMAT_R32_SFLOAT, 1,
                                   VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, "band pass depth (R32F)");
        bandDepth = image(VK_FORMAT_D32_SFLOAT, 1,
                          VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, "band pass depth");
        bandDepthBuffer = vk::Buffer(ctx, VkDeviceSize(w) * h * 4,
                                     VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, "band pass depth copy");
    }
}


LayeredView SpectralResources::mapTarget() {
    LayeredView a;
    if (plan.mappedReadback) {
        color.invalidate();
        VkImageSubresource sub{VK_IMAGE_ASPECT_COLOR_BIT, 0, 0};
        VkSubresourceLayout layout;
        vkGetImageSubresourceLayout(ctx.device(), color.handle(), &sub, &layout);
        a.base = static_cast<const char*>(color.mapped()) + layout.offset;
        a.rowPitch = layout.rowPitch;
        a.layerPitch = layout.arrayPitch;
        if (plan.layers > 1 && a.layerPitch == 0) {
            // Some drivers report no arrayPitch; ask for layer 1's offset instead.
            VkImageSubresource sub1{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1};
            VkSubresourceLayout l1;
            vkGetImageSubresourceLayout(ctx.device(), color.handle(), &sub1, &l1);
            a.layerPitch = l1.offset - layout.offset;
        }
    } else {
        readbackBuffer.invalidate();
        a.base = static_cast<const char*>(readbackBuffer.mapped());
        a.rowPitch = size_t(plan.targetWidth) * 16;
        a.layerPitch = a.rowPitch * plan.targetHeight;
    }
    return a;
}


}  // namespace metamer
