#include "render/spectral_resources.h"
#include "vk/render_pass.h"

#include "interface.h"
#include "lobe_lookup.h"
#include "vk/barrier.h"
#include "vk/pipeline.h"

#include "spectral.frag.1.spv.h"
#include "spectral.frag.2.spv.h"
#include "spectral.frag.3.spv.h"
#include "spectral.frag.4.spv.h"
#include "spectral.frag.5.spv.h"
#include "spectral.frag.6.spv.h"
#include "spectral.frag.7.spv.h"
#include "spectral.frag.8.spv.h"
#include "opaque_distance.frag.spv.h"
#include "transmit.frag.1.spv.h"
#include "transmit.frag.2.spv.h"
#include "transmit.frag.3.spv.h"
#include "transmit.frag.4.spv.h"
#include "transmit.frag.5.spv.h"
#include "transmit.frag.6.spv.h"
#include "transmit.frag.7.spv.h"
#include "transmit.frag.8.spv.h"
#include "spectral.vert.spv.h"

#include "core/timing.h"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <map>
#include <memory>
#include <cstddef>

namespace metamer {

namespace {

struct SpirvCode {
    const uint32_t* code;
    size_t bytes;
};
// spectral.frag built for 1..8 colour attachments (index = count - 1).
const SpirvCode kSpectralFrag[MAX_OUTPUTS] = {
    {kSpirv_spectral_frag_1, sizeof(kSpirv_spectral_frag_1)}, {kSpirv_spectral_frag_2, sizeof(kSpirv_spectral_frag_2)},
    {kSpirv_spectral_frag_3, sizeof(kSpirv_spectral_frag_3)}, {kSpirv_spectral_frag_4, sizeof(kSpirv_spectral_frag_4)},
    {kSpirv_spectral_frag_5, sizeof(kSpirv_spectral_frag_5)}, {kSpirv_spectral_frag_6, sizeof(kSpirv_spectral_frag_6)},
    {kSpirv_spectral_frag_7, sizeof(kSpirv_spectral_frag_7)}, {kSpirv_spectral_frag_8, sizeof(kSpirv_spectral_frag_8)},
};
// transmit.frag likewise.
const SpirvCode kTransmitFrag[MAX_OUTPUTS] = {
    {kSpirv_transmit_frag_1, sizeof(kSpirv_transmit_frag_1)}, {kSpirv_transmit_frag_2, sizeof(kSpirv_transmit_frag_2)},
    {kSpirv_transmit_frag_3, sizeof(kSpirv_transmit_frag_3)}, {kSpirv_transmit_frag_4, sizeof(kSpirv_transmit_frag_4)},
    {kSpirv_transmit_frag_5, sizeof(kSpirv_transmit_frag_5)}, {kSpirv_transmit_frag_6, sizeof(kSpirv_transmit_frag_6)},
    {kSpirv_transmit_frag_7, sizeof(kSpirv_transmit_frag_7)}, {kSpirv_transmit_frag_8, sizeof(kSpirv_transmit_frag_8)},
};

// spectral.vert's vertex input: one interleaved buffer of gpu::SpectralVertex.
void spectralVertexInput(vk::GraphicsPipelineDesc& d) {
    using V = gpu::SpectralVertex;
    d.bindings = {{0, sizeof(V), VK_VERTEX_INPUT_RATE_VERTEX}};
    d.attributes = {{VERTEX_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, uint32_t(offsetof(V, position))},
                    {VERTEX_NORMAL, 0, VK_FORMAT_R32G32B32_SFLOAT, uint32_t(offsetof(V, normal))},
                    {VERTEX_UV, 0, VK_FORMAT_R32G32_SFLOAT, uint32_t(offsetof(V, uv))},
                    {VERTEX_TANGENT, 0, VK_FORMAT_R32G32B32A32_SFLOAT, uint32_t(offsetof(V, tangent))}};
}

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
    hasTransmission = std::any_of(packed.draws.begin(), packed.draws.end(), [](const PackedDraw& d) { return d.transparent; });
    if (hasTransmission && packed.responses)
        failRuntime("the response pass cannot show transparent objects (radiance through a filter is not linear in "
                    "each material's spectra): render bands (render/display_frame.cpp does)");
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
        ctx.submitAndWait([&](VkCommandBuffer cmd) {
            const vk::ImageUse undefined{VK_IMAGE_LAYOUT_UNDEFINED, 0, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT};
            const vk::ImageUse copyTarget{VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT,
                                          VK_PIPELINE_STAGE_TRANSFER_BIT};
            const vk::ImageUse sampled{VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_SHADER_READ_BIT,
                                       VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT};
            vk::imageBarrier(cmd, image.handle(), layers, undefined, copyTarget);
            VkBufferImageCopy region{};
            region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, layers};
            region.imageExtent = {d.width, d.height, 1};
            vkCmdCopyBufferToImage(cmd, staging.handle(), image.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                                   &region);
            vk::imageBarrier(cmd, image.handle(), layers, copyTarget, sampled);
        });
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
    vk::ImageDesc dd;
    dd.format = VK_FORMAT_D32_SFLOAT;
    dd.width = w;
    dd.height = h;
    dd.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    dd.name = "depth";
    depth = vk::Image(ctx, dd);
    if (hasTransmission) {
        vk::ImageDesc od;
        od.format = VK_FORMAT_R32_SFLOAT;
        od.width = w;
        od.height = h;
        od.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
        od.name = "opaque distance";
        opaqueDistance = vk::Image(ctx, od);
    }
}

void SpectralResources::createLayouts() {
    VkDevice d = ctx.device();
    constexpr int kBindings = 12;
    constexpr int kDynamic = 4;  // bindings 1..4
    VkDescriptorSetLayoutBinding bindings[kBindings] = {
        {BINDING_LIGHTS, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        {BINDING_LIGHT_SPECTRA, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        {BINDING_MATERIAL, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        {BINDING_FLUORESCENCE, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        {BINDING_RESPONSES, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        {BINDING_SHADOW_MATRICES, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        {BINDING_SHADOW_MAP, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        {BINDING_LOBE_WEIGHTS, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        {BINDING_LOBE_TABLES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        {BINDING_OPAQUE_DISTANCE, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        {BINDING_SHADOW_TRANSMITTANCE, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        {BINDING_SHADOW_EXCITATION, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
    };
    VkDescriptorSetLayoutCreateInfo sl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    sl.bindingCount = kBindings;
    sl.pBindings = bindings;
    vk::DeviceObjects& objects = ctx.objects();
    setLayout = objects.setLayout("spectral.set", sl);
    VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                              sizeof(gpu::SpectralPushConstants)};
    VkDescriptorSetLayoutBinding textureBindings[TEXTURE_BINDINGS];
    for (uint32_t i = 0; i < TEXTURE_BINDINGS; ++i)
        textureBindings[i] = {i, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo tl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    tl.bindingCount = TEXTURE_BINDINGS;
    tl.pBindings = textureBindings;
    textureSetLayout = objects.setLayout("spectral.textures", tl);
    VkDescriptorSetLayout layouts[2] = {setLayout.get(), textureSetLayout.get()};
    VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pl.setLayoutCount = 2;
    pl.pSetLayouts = layouts;
    pl.pushConstantRangeCount = 1;
    pl.pPushConstantRanges = &range;
    pipelineLayout = objects.pipelineLayout("spectral.layout", pl, {setLayout, textureSetLayout});

    const uint32_t materialCount = uint32_t(std::max<size_t>(1, scene.materials.size()));
    // Three sets 0 (the band passes', the lobe pass's, the coloured shadows' passes'), one set 1 per material.
    VkDescriptorPoolSize sizes[4] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 3 * 2},
                                     {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 3 * kDynamic},
                                     {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, TEXTURE_BINDINGS * materialCount + 3 * 4},
                                     {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 3 * 2}};
    VkDescriptorPoolCreateInfo pci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pci.maxSets = 3 + materialCount;
    pci.poolSizeCount = 4;
    pci.pPoolSizes = sizes;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VK_CHECK(vkCreateDescriptorPool(d, &pci, nullptr, &pool));
    descriptorPool = vk::OwnedDescriptorPool(d, pool);
    VkDescriptorSetLayout set0 = setLayout.get();
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = pool;
    ai.descriptorSetCount = 1;
    ai.pSetLayouts = &set0;
    VK_CHECK(vkAllocateDescriptorSets(d, &ai, &descriptorSet));
    if (hasLobePass) VK_CHECK(vkAllocateDescriptorSets(d, &ai, &lobeDescriptorSet));
    if (packed.filteredShadows) VK_CHECK(vkAllocateDescriptorSets(d, &ai, &lightDescriptorSet));
    // Per binding, in the order of `bindings` (the two images' entries unused).
    VkDescriptorBufferInfo infos[kBindings] = {
        {lightBuffer.handle(), 0, sizeof(gpu::GpuLightBlock)},
        {lightSpectraBuffer.handle(), 0, sizeof(gpu::GpuLightSpectraBlock)},
        {materialBuffer.handle(), 0, sizeof(gpu::GpuMaterialBlock)},
        {fluorescenceBuffer.handle(), 0, sizeof(gpu::GpuFluorescenceBlock)},
        {responseBuffer.handle(), 0, sizeof(gpu::GpuResponseBlock)},
        {shadowBuffer.handle(), 0, sizeof(gpu::GpuShadowBlock)},
        {},
        {},
        {},
        {},
        {},
        {}};
    const VkBufferView view = lobeTableView.get();
    const VkDescriptorImageInfo shadowInfo{shadowSampler.get(), shadowMap->layerView(~0u),
                                           VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL};
    // The lobe weights, where a lobe pass writes them; else (and in the lobe pass's own set) the
    // placeholder texture, never read. Sampled with the textures' sampler (texelFetch only).
    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_NEAREST;
    sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkSampler sampler = VK_NULL_HANDLE;
    VK_CHECK(vkCreateSampler(d, &sci, nullptr, &sampler));
    textureSampler = vk::OwnedSampler(d, sampler);
    const VkDescriptorImageInfo placeholderInfo{sampler, textures.back().layerView(0), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    const VkDescriptorImageInfo lobeInfo =
        hasLobePass ? VkDescriptorImageInfo{sampler, lobeWeights.layerView(0), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}
                    : placeholderInfo;
    // The opaque surfaces' distance, where a transmission pass reads it; else the placeholder, never read.
    const VkDescriptorImageInfo opaqueDistanceInfo =
        hasTransmission ? VkDescriptorImageInfo{sampler, opaqueDistance.layerView(0), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}
                        : placeholderInfo;
    // The coloured shadows' transmittance, where the band passes read it (not in the set of the passes
    // that draw it); the excitation integrands.
    const VkDescriptorImageInfo placeholderArrayInfo{sampler, textures.back().layerView(~0u),
                                                     VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    const VkDescriptorImageInfo shadowTransmittanceInfo =
        packed.filteredShadows
            ? VkDescriptorImageInfo{sampler, shadowTransmittance.layerView(~0u), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}
            : placeholderArrayInfo;
    const VkDescriptorImageInfo lightDistanceInfo =
        packed.filteredShadows
            ? VkDescriptorImageInfo{sampler, lightDistance.layerView(0), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}
            : placeholderInfo;
    const VkBufferView excitationView = shadowExcitationView.get();
    for (VkDescriptorSet set : {descriptorSet, lobeDescriptorSet, lightDescriptorSet}) {
        if (set == VK_NULL_HANDLE) continue;
        VkWriteDescriptorSet writes[kBindings];
        for (int i = 0; i < kBindings; ++i) {
            writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
            writes[i].dstSet = set;
            writes[i].dstBinding = bindings[i].binding;
            writes[i].descriptorCount = 1;
            writes[i].descriptorType = bindings[i].descriptorType;
            if (bindings[i].binding == BINDING_SHADOW_MAP)
                writes[i].pImageInfo = &shadowInfo;
            else if (bindings[i].binding == BINDING_LOBE_WEIGHTS)
                writes[i].pImageInfo = set == descriptorSet ? &lobeInfo : &placeholderInfo;
            else if (bindings[i].binding == BINDING_OPAQUE_DISTANCE)
                writes[i].pImageInfo = set == lightDescriptorSet ? &lightDistanceInfo : &opaqueDistanceInfo;
            else if (bindings[i].binding == BINDING_SHADOW_TRANSMITTANCE)
                writes[i].pImageInfo = set == lightDescriptorSet ? &placeholderArrayInfo : &shadowTransmittanceInfo;
            else if (bindings[i].binding == BINDING_SHADOW_EXCITATION)
                writes[i].pTexelBufferView = &excitationView;
            else if (bindings[i].binding == BINDING_LOBE_TABLES)
                writes[i].pTexelBufferView = &view;
            else
                writes[i].pBufferInfo = &infos[i];
        }
        vkUpdateDescriptorSets(d, kBindings, writes, 0, nullptr);
    }

    // Set 1 per material: its textures, or the placeholder (texelFetch ignores the sampler's
    // filter; it must still be a valid sampler).
    std::vector<VkDescriptorSetLayout> setLayouts(materialCount, textureSetLayout.get());
    materialSets.resize(materialCount);
    VkDescriptorSetAllocateInfo mai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    mai.descriptorPool = pool;
    mai.descriptorSetCount = materialCount;
    mai.pSetLayouts = setLayouts.data();
    VK_CHECK(vkAllocateDescriptorSets(d, &mai, materialSets.data()));
    for (uint32_t m = 0; m < materialCount; ++m) {
        int slot[TEXTURE_BINDINGS] = {-1, -1, -1};
        if (m < materialTextures.size()) {
            slot[TEXTURE_BINDING_DIFFUSE] = materialTextures[m][0];
            slot[TEXTURE_BINDING_SPECULAR] = materialTextures[m][1];
            slot[TEXTURE_BINDING_NORMAL] = materialTextures[m][2];
        }
        VkDescriptorImageInfo images[TEXTURE_BINDINGS];
        VkWriteDescriptorSet tw[TEXTURE_BINDINGS];
        for (uint32_t i = 0; i < TEXTURE_BINDINGS; ++i) {
            vk::Image& image = slot[i] >= 0 ? textures[size_t(slot[i])] : textures.back();
            images[i] = {sampler, image.layerView(~0u), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
            tw[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
            tw[i].dstSet = materialSets[m];
            tw[i].dstBinding = i;
            tw[i].descriptorCount = 1;
            tw[i].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
            tw[i].pImageInfo = &images[i];
        }
        vkUpdateDescriptorSets(d, TEXTURE_BINDINGS, tw, 0, nullptr);
    }

    vert = vk::OwnedShaderModule(d, vk::createShaderModule(d, kSpirv_spectral_vert, sizeof(kSpirv_spectral_vert)));
}

// attachments == 0: the depth pre-pass (clears and writes depth). Otherwise a colour pass that
// loads the pre-pass's depth and shades only the visible surface (depth test EQUAL), so every
// pixel is shaded once per pass whatever the overdraw — or, clearsDepth, one with its own depth.
VkRenderPass SpectralResources::makeRenderPass(uint32_t attachments, bool clearsDepth) {
    vk::RenderPassDesc desc;
    const VkImageLayout finalLayout =
        plan.mappedReadback ? VK_IMAGE_LAYOUT_GENERAL : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    // Cleared once per frame by vkCmdClearColorImage in record(), not by the render pass: lavapipe
    // (Mesa 22.3) leaks about a target's size of memory per render-pass clear of array-layer views
    // (measured: +20 MB per frame at 256² × 89 bands).
    for (uint32_t i = 0; i < attachments; ++i)
        desc.colors.push_back({VK_FORMAT_R32G32B32A32_SFLOAT, VK_ATTACHMENT_LOAD_OP_LOAD, VK_ATTACHMENT_STORE_OP_STORE,
                               VK_IMAGE_LAYOUT_GENERAL, finalLayout});
    const bool prePass = clearsDepth;
    desc.depth = vk::AttachmentDesc{VK_FORMAT_D32_SFLOAT, prePass ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD,
                                    VK_ATTACHMENT_STORE_OP_STORE,  // every later pass loads it
                                    prePass ? VK_IMAGE_LAYOUT_UNDEFINED : VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
                                    VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    // The depth image is shared by every pass: wait for the pre-pass's depth writes.
    constexpr VkPipelineStageFlags depthStages =
        VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    desc.dependencies.push_back({true, depthStages, depthStages, VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT});
    renderPasses.push_back(vk::sharedRenderPass(
        ctx.objects(),
        fmt::format("spectral.pass attachments={} clearsDepth={} mapped={}", attachments, clearsDepth,
                    plan.mappedReadback),
        desc));
    return renderPasses.back().get();
}

// attachments == 0: the depth pre-pass pipeline (vertex stage only); writesDepth with attachments:
// a colour pass without a pre-pass.
VkPipeline SpectralResources::makePipeline(const vk::SharedHandle<VkRenderPass>& renderPass, uint32_t attachments,
                                           bool writesDepth, int lobeMode, const Variant& v) {
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
                                           packed.bandLayers};
    // interface.h orders the struct's 4-byte fields by id.
    constexpr uint32_t kIds = SPEC_BAND_LAYERS + 1;
    VkSpecializationMapEntry entries[kIds];
    for (uint32_t id = 0; id < kIds; ++id) entries[id] = {id, id * 4, 4};
    VkSpecializationInfo si{kIds, entries, sizeof(spec), &spec};
    bool prePass = attachments == 0;
    vk::GraphicsPipelineDesc d;
    d.cullMode = v.cullBackFaces ? VK_CULL_MODE_BACK_BIT : VK_CULL_MODE_NONE;
    d.renderPass = renderPass.get();
    d.layout = pipelineLayout.get();
    d.vertex = vert.get();
    d.fragmentSpecialization = &si;
    spectralVertexInput(d);
    d.width = plan.targetWidth;
    d.height = plan.targetHeight;
    d.colorAttachments = attachments;
    d.depthTest = true;
    d.cache = ctx.pipelineCache();
    d.depthWrite = writesDepth;
    // Same vertex shader (gl_Position is invariant) → the same depth in every pass.
    d.depthCompare = prePass ? VK_COMPARE_OP_LESS : writesDepth ? VK_COMPARE_OP_LESS_OR_EQUAL : VK_COMPARE_OP_EQUAL;
    // Everything the pipeline depends on is in its key (the render pass and layout are shared, so
    // their handles name their descriptions).
    const std::string key =
        fmt::format("spectral.pipeline attachments={} writesDepth={} cull={} {}x{} pass={} layout={} spec={}", attachments,
                    writesDepth, int(d.cullMode), d.width, d.height, static_cast<void*>(renderPass.get()),
                    static_cast<void*>(pipelineLayout.get()), vk::keyBytes(&spec, sizeof spec));
    pipelines.push_back(ctx.objects().pipeline(
        key,
        [&] {
            VkShaderModule frag = VK_NULL_HANDLE;
            if (!prePass) {
                const SpirvCode& fragCode = kSpectralFrag[attachments - 1];
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
        const bool closedMesh = std::any_of(packed.draws.begin(), packed.draws.end(),
                                            [&](const PackedDraw& d) { return d.closed && d.material == m; });
        if (closedMesh) {
            v.cullBackFaces = true;
            materialCulledVariant.back() = int32_t(index(v));
        }
    }
    if (variants.empty()) variants.push_back({});
}

std::vector<VkPipeline> SpectralResources::makePipelines(const vk::SharedHandle<VkRenderPass>& renderPass,
                                                         uint32_t attachments, bool writesDepth, int lobeMode) {
    std::vector<VkPipeline> out;
    for (const Variant& v : variants) out.push_back(makePipeline(renderPass, attachments, writesDepth, lobeMode, v));
    return out;
}

void SpectralResources::createPasses() {
    classifyDraws();
    // The band passes shade each pixel once behind a depth pre-pass. The response pass has one
    // pass, and the pre-pass pays there only where shading is costly enough for overdraw to
    // matter: textured materials (texel fetches per fragment). Measured at 1024²: textured.json
    // 30.9 → 27.9 ms; spheres.json (the environment lookup, back faces culled) 33.4 → 34.3 and
    // imaging-systems.json 25.2 → 24.1, noise either way (docs/performance.md).
    hasDepthPrePass = !plan.responses || scene.hasTextures();
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
    if (hasLobePass) createLobePass();
    if (hasTransmission) createTransmissionPasses();
    declareFrame();
}

// The depth pre-pass of a scene with transparent objects: it also writes the nearest opaque
// surface's distance (opaque_distance.frag) into an R32F image, left SHADER_READ_ONLY for the
// transmission passes. Pipelines: back faces kept, and culled.
vk::RenderPassDesc SpectralResources::distancePrePassDesc() const {
    vk::RenderPassDesc desc;
    desc.colors.push_back({VK_FORMAT_R32_SFLOAT, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_STORE,
                           VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
    desc.depth = vk::AttachmentDesc{VK_FORMAT_D32_SFLOAT, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_STORE,
                                    VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    constexpr VkPipelineStageFlags depthStages =
        VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    // The last frame's readers of the distance (the transmission passes) and of the depth, before.
    desc.dependencies.push_back({true, depthStages | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                                 depthStages | VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT,
                                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                                     VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT});
    // The distance, for the transmission passes' fragment shaders, after.
    desc.dependencies.push_back({false, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                                 VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT});
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
            d, kSpirv_opaque_distance_frag, sizeof(kSpirv_opaque_distance_frag)));
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
    const VkImageLayout targetLayout = plan.mappedReadback ? VK_IMAGE_LAYOUT_GENERAL : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    VkRenderPass rpFull = VK_NULL_HANDLE, rpLast = VK_NULL_HANDLE;
    VkPipeline plFull = VK_NULL_HANDLE, plLast = VK_NULL_HANDLE, reflectFull = VK_NULL_HANDLE, reflectLast = VK_NULL_HANDLE;
    const bool slabs = std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.isSlab(); });
    // The slabs' reflection draws add R·(ambient and hemisphere lights in the mirror direction).
    const gpu::TransmitSpecialization reflection{VK_FALSE, VK_TRUE, packed.ambient,
                                                 packed.ambient + packed.directional + packed.point, packed.hemisphere};
    VkSpecializationMapEntry entries[TRANSMIT_SPEC_HEMISPHERE_COUNT + 1];
    for (uint32_t id = 0; id <= TRANSMIT_SPEC_HEMISPHERE_COUNT; ++id) entries[id] = {id, id * 4, 4};
    const VkSpecializationInfo reflectionInfo{TRANSMIT_SPEC_HEMISPHERE_COUNT + 1, entries, sizeof reflection, &reflection};
    for (const PassObjects& band : passes) {
        PassObjects po;
        po.firstLayer = band.firstLayer;
        po.attachments = band.attachments;
        const bool full = po.attachments == MAX_OUTPUTS;
        VkRenderPass& rp = full ? rpFull : rpLast;
        VkPipeline& pl = full ? plFull : plLast;
        VkPipeline& reflect = full ? reflectFull : reflectLast;
        if (rp == VK_NULL_HANDLE) {
            vk::RenderPassDesc desc;
            for (uint32_t i = 0; i < po.attachments; ++i)
                desc.colors.push_back({VK_FORMAT_R32G32B32A32_SFLOAT, VK_ATTACHMENT_LOAD_OP_LOAD, VK_ATTACHMENT_STORE_OP_STORE,
                                       targetLayout, targetLayout});
            // The band pass's colour writes, before this pass blends onto them; after, the readback's copy.
            desc.dependencies.push_back({true, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                                         VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                                         VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT});
            desc.dependencies.push_back({false, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                                         VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT});
            renderPasses.push_back(vk::sharedRenderPass(
                ctx.objects(), fmt::format("spectral.transmission attachments={} mapped={}", po.attachments, plan.mappedReadback),
                desc));
            rp = renderPasses.back().get();
            const SpirvCode& code = kTransmitFrag[po.attachments - 1];
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
        }
        po.renderPass = rp;
        po.pipelines = {pl, reflect};
        std::vector<VkImageView> views;
        for (uint32_t i = 0; i < po.attachments; ++i) views.push_back(color.layerView(po.firstLayer + i));
        po.framebuffer = vk::createFramebuffer(ctx.device(), rp, views, plan.targetWidth, plan.targetHeight);
        transmissionPasses.push_back(std::move(po));
    }
}

// The lobe pass: one RGBA32F attachment, the pre-pass's depth loaded and tested EQUAL (each
// visible surface shaded once, as in the band passes), left SHADER_READ_ONLY for them.
void SpectralResources::createLobePass() {
    vk::RenderPassDesc desc;
    desc.colors.push_back({VK_FORMAT_R32G32B32A32_SFLOAT, VK_ATTACHMENT_LOAD_OP_DONT_CARE,  // read only where a surface is drawn
                           VK_ATTACHMENT_STORE_OP_STORE, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
    desc.depth = vk::AttachmentDesc{VK_FORMAT_D32_SFLOAT, VK_ATTACHMENT_LOAD_OP_LOAD, VK_ATTACHMENT_STORE_OP_STORE,
                                    VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
                                    VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    constexpr VkPipelineStageFlags depthStages =
        VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    // The pre-pass's depth writes before; the weights, for the band passes' fragment shaders, after.
    desc.dependencies.push_back({true, depthStages, depthStages | VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT});
    desc.dependencies.push_back({false, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                                 VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT});
    renderPasses.push_back(vk::sharedRenderPass(
        ctx.objects(), fmt::format("spectral.lobe pass {}x{}", plan.targetWidth, plan.targetHeight), desc));
    lobePass.renderPass = renderPasses.back().get();
    lobePass.attachments = 1;
    lobePass.pipelines = makePipelines(renderPasses.back(), 1, false, LOBE_WRITE);
    lobePass.framebuffer = vk::createFramebuffer(ctx.device(), lobePass.renderPass,
                                                 {lobeWeights.layerView(0), depth.layerView(0)}, plan.targetWidth,
                                                 plan.targetHeight);
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
        dd, kSpirv_opaque_distance_frag, sizeof(kSpirv_opaque_distance_frag));
    const vk::OwnedFramebuffer distanceFramebuffer =
        vk::createFramebuffer(ctx.device(), distancePass, {lightDistance.layerView(0), lightDepth.layerView(0)}, size, size);
    // One render pass and pipeline per attachment count: clear to 0, add the optical depths.
    std::map<uint32_t, std::pair<VkRenderPass, VkPipeline>> byCount;
    for (const PassObjects& band : passes) {
        if (byCount.count(band.attachments)) continue;
        vk::RenderPassDesc desc;
        for (uint32_t i = 0; i < band.attachments; ++i)
            desc.colors.push_back({VK_FORMAT_R32G32B32A32_SFLOAT, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_STORE,
                                   VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
        desc.dependencies.push_back({false, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                                     VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT});
        renderPasses.push_back(vk::sharedRenderPass(
            ctx.objects(), fmt::format("spectral.shadow transmittance attachments={}", band.attachments), desc));
        const VkRenderPass rp = renderPasses.back().get();
        const SpirvCode& code = kTransmitFrag[band.attachments - 1];
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
    std::vector<FramePass> lightPasses;
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
        lightPasses.push_back({fmt::format("light distance {}", layer), "the opaque triangles seen from the light",
                               "their distance from the light", "opaque_distance.frag", distancePass,
                               distanceFramebuffer.get(), {size, size}, {noSurface, farDepth},
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
            lightPasses.push_back({fmt::format("shadow transmittance {} band pass {}", layer, p),
                                   "the light's distance; the transparent triangles", "the light's transmittance",
                                   "transmit.frag", rp, framebuffers.back().get(), {size, size},
                                   std::vector<VkClearValue>(passes[p].attachments, clear),
                                   [this, f, p, pipeline](VkCommandBuffer cmd) {
                                       drawTransparent(cmd, *f, p, pipeline, lightDescriptorSet);
                                   }});
        }
        eyes.push_back(std::move(cm));
        states.push_back(std::move(state));
    }
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        for (const FramePass& pass : lightPasses) recordFramePass(cmd, pass);
    });
    shadowMs += msSince(t0);
}

}  // namespace metamer
