// The shadow maps' depth passes (SpectralResources::createShadowMaps): each layer of
// render/shadow_maps.h's plan drawn once, depth only, with a slope-scaled bias, as a Frame
// (render/frame_pass.h) that leaves the image sampled (DEPTH_STENCIL_READ_ONLY_OPTIMAL) for the
// spectral passes' depth-compare sampler.
#include "core/timing.h"
#include "render/frame_pass.h"
#include "vk/render_pass.h"
#include "interface.h"
#include "render/spectral_resources.h"
#include "vk/pipeline.h"

#include "shadow.vert.spv.h"

#include <cstddef>

namespace metamer {

namespace {

// Depth bias of the depth pass, in the units of vkCmdSetDepthBias: the constant term is negligible
// for a float depth buffer; the slope term pushes each texel's depth back by what its surface's
// slope makes of 2 texels, which, with the lookup's one-texel normal offset, keeps every bundled
// surface free of self-shadowing (docs/physics.md, "Shadows").
constexpr float kDepthBiasConstant = 1.0f;
constexpr float kDepthBiasSlope = 2.0f;

}  // namespace

namespace {

template <typename T>
void appendBytes(std::string& key, const T* data, size_t count) {
    key.append(reinterpret_cast<const char*>(data), count * sizeof(T));
}

// Everything the shadow maps are drawn from, byte for byte: the map size and layers, each layer's
// matrix, the positions, the indices and the opaque draws. Not the camera, the materials or the
// image size: a batch's jobs that change only those reuse the maps (issue 31).
std::string shadowMapKey(const PackedScene& packed, uint32_t size, uint32_t layers) {
    std::string key = fmt::format("shadow maps v1 {} {}\n", size, layers);
    appendBytes(key, packed.shadowBlock.layers, std::min<size_t>(layers, MAX_SHADOW_LAYERS));
    for (const gpu::SpectralVertex& v : packed.vertices) appendBytes(key, v.position, 3);
    appendBytes(key, packed.indices.data(), packed.indices.size());
    for (const PackedDraw& d : packed.draws)
        if (!d.transparent) {
            appendBytes(key, &d.firstIndex, 1);
            appendBytes(key, &d.indexCount, 1);
            appendBytes(key, &d.vertexOffset, 1);
        }
    return key;
}

}  // namespace

void SpectralResources::drawShadowMaps(vk::Image& shadowImage, uint32_t size, uint32_t layers) {
    VkDevice d = ctx.device();
    const ShadowMaps& maps = packed.shadowMaps;
    // One render pass: clear, draw.
    vk::RenderPassDesc passDesc;
    passDesc.depth = vk::attachmentFor(VK_FORMAT_D32_SFLOAT, vk::Access::DepthAttachment, VK_ATTACHMENT_LOAD_OP_CLEAR);
    VkRenderPass renderPass = vk::createRenderPass(d, passDesc);
    const vk::OwnedRenderPass ownedPass(d, renderPass);

    VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(gpu::ShadowPushConstants)};
    VkPipelineLayoutCreateInfo plci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    plci.pushConstantRangeCount = 1;
    plci.pPushConstantRanges = &range;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VK_CHECK(vkCreatePipelineLayout(d, &plci, nullptr, &layout));
    const vk::OwnedPipelineLayout ownedLayout(d, layout);

    std::vector<vk::OwnedFramebuffer> framebuffers;
    for (uint32_t l = 0; l < layers; ++l)
        framebuffers.push_back(vk::createFramebuffer(d, renderPass, {shadowImage.layerView(l)}, size, size));

    vk::OwnedPipeline pipeline;
    const bool draws = maps.any() && !packed.draws.empty();
    if (draws) {
        const vk::OwnedShaderModule vertex(d, vk::createShaderModule(d, kSpirv_shadow_vert, sizeof(kSpirv_shadow_vert)));
        vk::GraphicsPipelineDesc pd;
        pd.renderPass = renderPass;
        pd.layout = layout;
        pd.vertex = vertex.get();
        using V = gpu::SpectralVertex;
        pd.bindings = {{0, sizeof(V), VK_VERTEX_INPUT_RATE_VERTEX}};
        pd.attributes = {{VERTEX_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, uint32_t(offsetof(V, position))}};
        pd.width = pd.height = size;
        pd.depthTest = pd.depthWrite = true;
        pd.depthCompare = VK_COMPARE_OP_LESS;
        pd.depthBiasConstant = kDepthBiasConstant;
        pd.depthBiasSlope = kDepthBiasSlope;
        pd.cache = ctx.pipelineCache();
        pipeline = vk::OwnedPipeline(d, vk::createGraphicsPipeline(d, pd));
    }

    // One declared pass per layer (render/frame_pass.h), recorded once: the maps depend on the
    // scene, not the camera. The image is new, and left for the fragment shaders to sample.
    Frame shadowPasses;
    const size_t image =
        shadowPasses.add(FrameResource::madeFor("shadow maps", shadowImage.handle(), layers, {vk::Access::Sampled, true, true}));
    std::vector<ResourceUse> geometry;
    if (!packed.vertices.empty())
        for (const auto& [name, buffer] : {std::pair{"vertices", &vertexBuffer}, std::pair{"indices", &indexBuffer}})
            geometry.push_back(
                {shadowPasses.add(FrameResource::settled(name, buffer->handle(), vk::Access::VertexInput)), vk::Access::VertexInput});
    for (uint32_t l = 0; l < layers; ++l) {
        std::vector<ResourceUse> uses = geometry;
        uses.push_back({image, vk::Access::DepthAttachment, l, 1, false});
        shadowPasses.add(FramePass{
             fmt::format("shadow map layer {}", l), "depth only, slope-scaled bias", std::move(uses), renderPass,
             framebuffers[l].get(), {size, size}, {VkClearValue{.depthStencil = {1.0f, 0}}}, [&, l](VkCommandBuffer cmd) {
                 if (!draws) return;
                 vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.get());
                 VkDeviceSize zero = 0;
                 VkBuffer vb = vertexBuffer.handle();
                 vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &zero);
                 vkCmdBindIndexBuffer(cmd, indexBuffer.handle(), 0, VK_INDEX_TYPE_UINT32);
                 gpu::ShadowPushConstants pc{packed.shadowBlock.layers[l]};
                 vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof pc, &pc);
                 for (const PackedDraw& draw : packed.draws)
                     if (!draw.transparent)  // filters and media colour the light instead (the transmittance maps)
                         vkCmdDrawIndexed(cmd, draw.indexCount, 1, draw.firstIndex, draw.vertexOffset, 0);
             }});
    }
    shadowPasses.derive();
    ctx.submitAndWait([&](VkCommandBuffer cmd) { recordFrame(cmd, shadowPasses); });
}

void SpectralResources::createShadowMaps() {
    auto t0 = Clock::now();
    VkDevice d = ctx.device();
    const ShadowMaps& maps = packed.shadowMaps;
    const uint32_t size = maps.any() ? SHADOW_MAP_SIZE : 1, layers = uint32_t(std::max<size_t>(1, maps.layers.size()));
    shadowBuffer = uniforms(&packed.shadowBlock, sizeof(gpu::GpuShadowBlock), 1, sizeof(gpu::GpuShadowBlock), "shadow matrices");

    // Depth compare, no filtering: a texel is lit when the fragment's depth is at most the map's.
    // Outside the map the border (depth 1) lights it.
    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_NEAREST;
    sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER;
    sci.borderColor = VK_BORDER_COLOR_FLOAT_OPAQUE_WHITE;
    sci.compareEnable = VK_TRUE;
    sci.compareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
    VkSampler sampler = VK_NULL_HANDLE;
    VK_CHECK(vkCreateSampler(d, &sci, nullptr, &sampler));
    shadowSampler = vk::OwnedSampler(d, sampler);

    // Drawn once per scene and device: a later render of the same geometry and lights (a batch's
    // next job, the preview after a material change) takes the maps as they are. Two are kept.
    shadowMap = std::static_pointer_cast<vk::Image>(ctx.objects().reusable(shadowMapKey(packed, size, layers), [&] {
        vk::ImageDesc desc;
        desc.format = VK_FORMAT_D32_SFLOAT;
        desc.width = desc.height = size;
        desc.layers = layers;
        desc.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
        desc.name = "shadow maps";
        auto image = std::make_shared<vk::Image>(ctx, desc);
        drawShadowMaps(*image, size, layers);
        return std::static_pointer_cast<void>(image);
    }, 2));
    shadowMs = msSince(t0);
}

}  // namespace metamer
