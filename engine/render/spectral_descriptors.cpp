// The spectral frame's descriptor set layouts, pipeline layout and sets (SpectralResources::
// createLayouts): set 0 — the uniform blocks, shadow maps, lobe tables and weights, the opaque
// distance and the coloured shadows (maps and channel spectra) — three times (the band passes', the lobe pass's, the coloured
// shadows' passes'), and set 1 per material (its textures). Binding numbers from shaders/interface.h.
// Tests: through render/spectral_pass.h's (every GPU test, validation layers on).
#include "render/spectral_resources.h"

#include "interface.h"
#include "render/spectral_shaders.h"

namespace metamer {

void SpectralResources::createLayouts() {
    VkDevice d = ctx.device();
    constexpr int kBindings = 15;
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
        {BINDING_DEPTH_SPECTRA, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        {BINDING_VIEW_CHANNELS, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        {BINDING_SLAB_DISTANCE, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
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
    // Four sets 0 (the band passes', the lobe pass's, the coloured shadows' passes', the channel
    // pass's — which writes the view channels the others read), one set 1 per material.
    VkDescriptorPoolSize sizes[4] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 4 * 2},
                                     {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 4 * kDynamic},
                                     {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, TEXTURE_BINDINGS * materialCount + 4 * 6},
                                     {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 4 * 3}};
    VkDescriptorPoolCreateInfo pci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pci.maxSets = 4 + materialCount;
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
    if (viewChannelLayers > 0) VK_CHECK(vkAllocateDescriptorSets(d, &ai, &channelDescriptorSet));
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
        {},
        {},
        {},
        {}};
    const VkBufferView view = lobeTableView.get();
    // The layouts the frame's passes sample in (render/frame_pass.h derives the transitions there).
    const VkImageLayout sampled = vk::accessLayout(vk::Access::Sampled);
    const VkDescriptorImageInfo shadowInfo{shadowSampler.get(), shadowMap->layerView(~0u),
                                           vk::accessLayout(vk::Access::Sampled, true)};
    // The lobe weights, where a lobe pass writes them; else (and in the lobe pass's own set) the
    // placeholder texture, never read. Sampled with the textures' sampler (texelFetch only).
    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_NEAREST;
    sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkSampler sampler = VK_NULL_HANDLE;
    VK_CHECK(vkCreateSampler(d, &sci, nullptr, &sampler));
    textureSampler = vk::OwnedSampler(d, sampler);
    const VkDescriptorImageInfo placeholderInfo{sampler, textures.back().layerView(0), sampled};
    const VkDescriptorImageInfo lobeInfo =
        hasLobePass ? VkDescriptorImageInfo{sampler, lobeWeights.layerView(0), sampled}
                    : placeholderInfo;
    // The opaque surfaces' distance, where a transmission pass reads it; else the placeholder, never read.
    const VkDescriptorImageInfo opaqueDistanceInfo =
        hasTransmission ? VkDescriptorImageInfo{sampler, opaqueDistance.layerView(0), sampled}
                        : placeholderInfo;
    // The coloured shadows' transmittance, where the band passes read it (not in the set of the passes
    // that draw it); the excitation integrands.
    const VkDescriptorImageInfo placeholderArrayInfo{sampler, textures.back().layerView(~0u),
                                                     sampled};
    const VkDescriptorImageInfo shadowTransmittanceInfo =
        packed.filteredShadows
            ? VkDescriptorImageInfo{sampler, shadowTransmittance.layerView(~0u), sampled}
            : placeholderArrayInfo;
    const VkDescriptorImageInfo lightDistanceInfo =
        packed.filteredShadows
            ? VkDescriptorImageInfo{sampler, lightDistance.layerView(0), sampled}
            : placeholderInfo;
    // The camera's optical-depth channels, where the band passes read them; else the placeholder.
    const VkDescriptorImageInfo viewChannelsInfo =
        viewChannelLayers > 0 ? VkDescriptorImageInfo{sampler, viewChannels.layerView(~0u), sampled} : placeholderArrayInfo;
    const VkDescriptorImageInfo slabDistanceInfo =
        viewSplit ? VkDescriptorImageInfo{sampler, slabDistance.layerView(0), sampled} : placeholderInfo;
    const VkBufferView excitationView = shadowExcitationView.get(), depthView = depthSpectraView.get();
    for (VkDescriptorSet set : {descriptorSet, lobeDescriptorSet, lightDescriptorSet, channelDescriptorSet}) {
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
            else if (bindings[i].binding == BINDING_SLAB_DISTANCE)
                writes[i].pImageInfo = set == descriptorSet || set == channelDescriptorSet ? &slabDistanceInfo : &placeholderInfo;
            else if (bindings[i].binding == BINDING_VIEW_CHANNELS)
                writes[i].pImageInfo = set == descriptorSet ? &viewChannelsInfo : &placeholderArrayInfo;
            else if (bindings[i].binding == BINDING_DEPTH_SPECTRA)
                writes[i].pTexelBufferView = &depthView;
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
            images[i] = {sampler, image.layerView(~0u), sampled};
            tw[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
            tw[i].dstSet = materialSets[m];
            tw[i].dstBinding = i;
            tw[i].descriptorCount = 1;
            tw[i].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
            tw[i].pImageInfo = &images[i];
        }
        vkUpdateDescriptorSets(d, TEXTURE_BINDINGS, tw, 0, nullptr);
    }

    vert = vk::OwnedShaderModule(d, vk::createShaderModule(d, spectralVertex().code, spectralVertex().bytes));
    if (!packed.indirect.empty())
        vertIndirect = vk::OwnedShaderModule(d, vk::createShaderModule(d, spectralIndirectVertex().code,
                                                                        spectralIndirectVertex().bytes));
}


}  // namespace metamer
