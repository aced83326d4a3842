#include "render/tonemap_pass.h"
#include "render/frame_pass.h"
#include "vk/render_pass.h"

#include "interface.h"
#include "vk/device_objects.h"
#include "vk/handle.h"
#include "vk/pipeline.h"
#include "vk/resources.h"

#include "tonemap.frag.spv.h"
#include "tonemap.vert.spv.h"

#include <chrono>
#include <cstring>

namespace metamer {

namespace {

constexpr uint32_t kAttachments = 4;  // counts, XYZ, responses 0–3, responses 4–7

void setRows(glm::vec4 rows[3], const glm::dmat3& m) {
    for (int r = 0; r < 3; ++r) rows[r] = glm::vec4(float(m[0][r]), float(m[1][r]), float(m[2][r]), 0.0f);
}

// Appends per-band values as one vec4 per layer (4 bands), zero past the last band.
uint32_t appendLayers(std::vector<glm::vec4>& tables, const std::vector<double>& bands, int layers) {
    uint32_t offset = uint32_t(tables.size());
    for (int l = 0; l < layers; ++l) {
        glm::vec4 v(0.0f);
        for (int c = 0; c < 4; ++c) {
            size_t b = size_t(l) * 4 + c;
            if (b < bands.size()) v[c] = float(bands[b]);
        }
        tables.push_back(v);
    }
    return offset;
}


}  // namespace

struct TonemapPass::Impl {
    vk::Context& ctx;
    SpectralPass& source;
    const TonemapPlan& plan;
    TonemapOutputs outputs;
    uint32_t width, height;
    int layers;
    vk::Buffer params, tables, readback;
    vk::Image targets[kAttachments];
    vk::OwnedSampler sampler;
    // Shared with every tonemap pass of the same configuration (vk/device_objects.h).
    vk::SharedHandle<VkDescriptorSetLayout> setLayout;
    vk::SharedHandle<VkPipelineLayout> pipelineLayout;
    vk::OwnedDescriptorPool pool;  // frees `set` with it
    VkDescriptorSet set = VK_NULL_HANDLE;
    vk::SharedHandle<VkRenderPass> renderPass;
    vk::OwnedFramebuffer framebuffer;
    vk::SharedHandle<VkPipeline> pipeline;
    Frame frame;

    Impl(vk::Context& c, SpectralPass& s, const TonemapPlan& p, TonemapOutputs o) : ctx(c), source(s), plan(p), outputs(o) {}

    // Whether attachment i is read back.
    bool wanted(uint32_t i) const {
        const bool colorimetric = plan.mode != TonemapMode::ResponsesOnly;
        switch (i) {
            case TONEMAP_OUT_COUNTS: return outputs.counts && colorimetric;
            case TONEMAP_OUT_XYZ: return outputs.xyz && colorimetric;
            case TONEMAP_OUT_RESPONSES: return outputs.responses;
            default: return outputs.responses && plan.detector.weights.size() > 4;
        }
    }

    void createBuffers() {
        gpu::TonemapParams p{};
        setRows(p.responseToXyz, plan.responseToXyz);
        setRows(p.adaptation, plan.adaptation);
        setRows(p.xyzToRgb, glm::inverse(plan.display.rgbToXyz));
        p.blackXyz = glm::vec4(glm::vec3(plan.display.blackXyz), float(maxCount(plan.display)));
        p.gain = glm::vec4(glm::vec3(plan.display.gain), 0.0f);
        p.offset = glm::vec4(glm::vec3(plan.display.offset), 0.0f);
        p.gamma = glm::vec4(glm::vec3(plan.display.gamma), 0.0f);
        p.cutoffCounts = glm::vec4(glm::vec3(cutoffCounts(plan.display)), 0.0f);
        p.scales = glm::vec4(float(plan.xyzOutputScale), 1.0f / float(source.plan().ssaa * source.plan().ssaa), 0, 0);

        std::vector<glm::vec4> t;
        p.weightsOffset = uint32_t(t.size());
        for (const auto& w : plan.detector.weights) appendLayers(t, w, layers);
        if (plan.film) {
            const FilmModel& f = *plan.film;
            for (int i = 0; i < 3; ++i)
                p.filmCurve[i] = glm::vec4(float(f.curves[i].dMin), float(f.curves[i].dMax), float(f.curves[i].logH0),
                                           float(f.curves[i].gamma));
            p.filmToe = glm::vec4(float(f.curves[0].toe), float(f.curves[1].toe), float(f.curves[2].toe), 0.0f);
            p.filmWhite = glm::vec4(glm::vec3(f.exposureOfWhite), float(1.0 / f.projectedWhiteY));
            p.dyeOffset = uint32_t(t.size());
            for (int i = 0; i < 3; ++i) appendLayers(t, f.dyeDensity[i], layers);
            p.baseOffset = appendLayers(t, f.baseDensity, layers);
            p.projectionOffset = uint32_t(t.size());
            for (int i = 0; i < 3; ++i) appendLayers(t, f.projection[i], layers);
        }
        if (t.empty()) t.push_back(glm::vec4(0.0f));
        params = vk::Buffer(ctx, sizeof(p), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, "tonemap params");
        params.upload(&p, sizeof(p));
        tables = vk::Buffer(ctx, t.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "tonemap tables");
        tables.upload(t.data(), t.size() * sizeof(glm::vec4));
        readback = vk::Buffer(ctx, VkDeviceSize(width) * height * 16 * kAttachments, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                              "tonemap readback");
    }

    void createTargets() {
        const char* names[kAttachments] = {"counts", "xyz", "responses 0-3", "responses 4-7"};
        for (uint32_t i = 0; i < kAttachments; ++i) {
            vk::ImageDesc d;
            d.width = width;
            d.height = height;
            d.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
            d.name = names[i];
            targets[i] = vk::Image(ctx, d);
        }
    }

    void createPipeline() {
        VkDevice d = ctx.device();
        VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
        sci.magFilter = sci.minFilter = VK_FILTER_NEAREST;
        sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
        VK_CHECK(vkCreateSampler(d, &sci, nullptr, sampler.put(d)));

        VkDescriptorSetLayoutBinding b[3] = {
            {TONEMAP_BINDING_SPECTRAL, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
            {TONEMAP_BINDING_PARAMS, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
            {TONEMAP_BINDING_TABLES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        };
        VkDescriptorSetLayoutCreateInfo sl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        sl.bindingCount = 3;
        sl.pBindings = b;
        vk::DeviceObjects& objects = ctx.objects();
        setLayout = objects.setLayout("tonemap.set", sl);
        const VkDescriptorSetLayout layout = setLayout.get();
        VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        pl.setLayoutCount = 1;
        pl.pSetLayouts = &layout;
        pipelineLayout = objects.pipelineLayout("tonemap.layout", pl, {setLayout});

        VkDescriptorPoolSize sizes[3] = {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1},
                                         {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1},
                                         {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1}};
        VkDescriptorPoolCreateInfo pci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        pci.maxSets = 1;
        pci.poolSizeCount = 3;
        pci.pPoolSizes = sizes;
        VK_CHECK(vkCreateDescriptorPool(d, &pci, nullptr, pool.put(d)));
        VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        ai.descriptorPool = pool.get();
        ai.descriptorSetCount = 1;
        ai.pSetLayouts = &layout;
        VK_CHECK(vkAllocateDescriptorSets(d, &ai, &set));
        VkDescriptorImageInfo image{sampler.get(), source.targetArrayView(), vk::accessLayout(vk::Access::Sampled)};
        VkDescriptorBufferInfo ubo{params.handle(), 0, VK_WHOLE_SIZE}, ssbo{tables.handle(), 0, VK_WHOLE_SIZE};
        VkWriteDescriptorSet w[3];
        for (int i = 0; i < 3; ++i) {
            w[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
            w[i].dstSet = set;
            w[i].dstBinding = b[i].binding;
            w[i].descriptorCount = 1;
            w[i].descriptorType = b[i].descriptorType;
        }
        w[0].pImageInfo = &image;
        w[1].pBufferInfo = &ubo;
        w[2].pBufferInfo = &ssbo;
        vkUpdateDescriptorSets(d, 3, w, 0, nullptr);

        vk::RenderPassDesc desc;
        for (uint32_t i = 0; i < kAttachments; ++i)  // DONT_CARE: every pixel is written
            desc.colors.push_back(vk::attachmentFor(VK_FORMAT_R32G32B32A32_SFLOAT, vk::Access::ColorAttachment,
                                                    VK_ATTACHMENT_LOAD_OP_DONT_CARE));
        renderPass = vk::sharedRenderPass(objects, "tonemap.pass", desc);
        std::vector<VkImageView> views;
        for (uint32_t i = 0; i < kAttachments; ++i) views.push_back(targets[i].layerView(0));
        framebuffer = vk::createFramebuffer(d, renderPass.get(), views, width, height);

        const gpu::TonemapSpecialization spec{
            int32_t(std::max<size_t>(1, plan.detector.weights.size())), layers, source.plan().ssaa,
            plan.mode == TonemapMode::Film     ? TONEMAP_MODE_FILM
            : plan.mode == TonemapMode::Linear ? TONEMAP_MODE_LINEAR
                                               : TONEMAP_MODE_RESPONSES,
            plan.display.kind == DisplayKind::Srgb ? TONEMAP_DISPLAY_SRGB : TONEMAP_DISPLAY_GOG,
            source.plan().responses ? TONEMAP_INPUT_RESPONSES : TONEMAP_INPUT_BANDS};
        const VkSpecializationInfo si = vk::specializationOf(spec);
        const std::string key = fmt::format("tonemap.pipeline {}x{} pass={} layout={} spec={}", width, height,
                                            static_cast<void*>(renderPass.get()),
                                            static_cast<void*>(pipelineLayout.get()), vk::keyBytes(&spec, sizeof spec));
        pipeline = objects.pipeline(
            key,
            [&] {
                // The pipeline keeps what it needs of the modules.
                const vk::OwnedShaderModule vert(d, vk::createShaderModule(d, kSpirv_tonemap_vert, sizeof(kSpirv_tonemap_vert)));
                const vk::OwnedShaderModule frag(d, vk::createShaderModule(d, kSpirv_tonemap_frag, sizeof(kSpirv_tonemap_frag)));
                vk::GraphicsPipelineDesc desc;
                desc.renderPass = renderPass.get();
                desc.layout = pipelineLayout.get();
                desc.vertex = vert.get();
                desc.fragment = frag.get();
                desc.fragmentSpecialization = &si;
                desc.cache = ctx.pipelineCache();
                desc.width = width;
                desc.height = height;
                desc.colorAttachments = kAttachments;
                return vk::createGraphicsPipeline(d, desc);
            },
            {renderPass, pipelineLayout});
        declareFrame();
    }

    // The frame (render/frame_pass.h): the tonemap pass, a full-screen triangle writing every pixel
    // of its four targets, then the copy of the wanted ones and the host's read. The spectral target
    // is borrowed: it enters as the spectral pass's frame left it and is handed back so.
    void declareFrame() {
        using vk::Access;
        FrameResource borrowed = FrameResource::perFrame("spectral target", source.targetImage(), uint32_t(source.plan().layers));
        borrowed.entry = borrowed.exit = source.targetState();
        const size_t spectral = frame.add(std::move(borrowed));
        const size_t uniforms = frame.add(FrameResource::settled("tonemap params", params.handle(), Access::UniformRead));
        const size_t storage = frame.add(FrameResource::settled("tonemap tables", tables.handle(), Access::StorageRead));
        std::vector<ResourceUse> uses{{spectral, Access::Sampled}, {uniforms, Access::UniformRead}, {storage, Access::StorageRead}};
        size_t target[kAttachments];
        for (uint32_t i = 0; i < kAttachments; ++i) {
            target[i] = frame.add(FrameResource::perFrame(targets[i].desc().name, targets[i].handle()));
            uses.push_back({target[i], Access::ColorAttachment, 0, kAllLayers, false});
        }
        frame.add(FramePass{"tonemap", "the detector's channels, the tonemap mode, the display model, the input",
                            std::move(uses), renderPass.get(), framebuffer.get(), {width, height}, {},
                            [this](VkCommandBuffer cmd) {
                                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.get());
                                vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelineLayout.get(), 0, 1,
                                                        &set, 0, nullptr);
                                vkCmdDraw(cmd, 3, 1, 0, 0);
                            }});
        const size_t buffer = frame.add(FrameResource::perFrame("tonemap readback", readback.handle()));
        std::vector<ResourceUse> copied{{buffer, Access::TransferDst}};
        for (uint32_t i = 0; i < kAttachments; ++i)
            if (wanted(i)) copied.push_back({target[i], Access::TransferSrc});
        frame.add(FramePass{"tonemap readback", "vkCmdCopyImageToBuffer of the outputs asked for", std::move(copied),
                            VK_NULL_HANDLE, VK_NULL_HANDLE, {}, {}, [this](VkCommandBuffer cmd) {
                                for (uint32_t i = 0; i < kAttachments; ++i) {
                                    if (!wanted(i)) continue;
                                    VkBufferImageCopy region{};
                                    region.bufferOffset = VkDeviceSize(i) * width * height * 16;
                                    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                                    region.imageExtent = {width, height, 1};
                                    vkCmdCopyImageToBuffer(cmd, targets[i].handle(), vk::accessLayout(vk::Access::TransferSrc),
                                                           readback.handle(), 1, &region);
                                }
                            }});
        frame.add(FramePass{"host read", "the host maps the readback buffer", {{buffer, Access::HostRead}}});
        frame.derive();
    }

    DisplayImage read() {
        readback.invalidate();
        const float* base = static_cast<const float*>(readback.mapped());
        size_t n = size_t(width) * height;
        DisplayImage img;
        img.width = int(width);
        img.height = int(height);
        img.channels = int(plan.detector.weights.size());
        const float* counts = base;
        const float* xyz = base + 4 * n;
        const float* r0 = base + 8 * n;
        const float* r1 = base + 12 * n;
        if (wanted(TONEMAP_OUT_RESPONSES)) {
            img.responses.resize(n * img.channels);
            for (size_t i = 0; i < n; ++i)
                for (int c = 0; c < img.channels; ++c)
                    img.responses[i * img.channels + c] = c < 4 ? r0[4 * i + c] : r1[4 * i + c - 4];
        }
        if (wanted(TONEMAP_OUT_XYZ)) {
            img.xyz.resize(n * 3);
            for (size_t i = 0; i < n; ++i)
                for (int c = 0; c < 3; ++c) img.xyz[3 * i + c] = xyz[4 * i + c];
        }
        if (wanted(TONEMAP_OUT_COUNTS)) {
            img.counts.resize(n * 3);
            img.clipped.resize(n);
            for (size_t i = 0; i < n; ++i) {
                img.clipped[i] = counts[4 * i + 3] > 0.5f;
                for (int c = 0; c < 3; ++c) img.counts[3 * i + c] = uint16_t(counts[4 * i + c]);
                img.clippedPixels += counts[4 * i + 3] > 0.5f;
            }
        }
        return img;
    }
};

TonemapPass::TonemapPass(vk::Context& ctx, SpectralPass& source, const TonemapPlan& plan, TonemapOutputs outputs)
    : impl_(std::make_unique<Impl>(ctx, source, plan, outputs)) {
    if (plan.detector.weights.size() > TONEMAP_MAX_CHANNELS)
        failInput(Where{"", "--detector"}, "{} channels; the tonemap pass takes at most {}", plan.detector.weights.size(),
                  TONEMAP_MAX_CHANNELS);
    Impl& m = *impl_;
    m.width = source.plan().targetWidth / uint32_t(source.plan().ssaa);
    m.height = source.plan().targetHeight / uint32_t(source.plan().ssaa);
    // The tables are per band of the plan's grid (its channels in a reduced mode); the band
    // spectral pass's target has as many layers, the response pass's holds the responses.
    m.layers = plan.grid.layers();
    if (!source.plan().responses && source.plan().layers != m.layers)
        failRuntime("the tonemap plan is on {} bands, the spectral pass on {}", plan.grid.bands(), source.plan().bands);
    if (source.plan().responses && source.plan().bands != int(plan.detector.weights.size()))
        failRuntime("the response pass carries {} channels, the detector has {}", source.plan().bands,
                    plan.detector.weights.size());
    m.createBuffers();
    m.createTargets();
    m.createPipeline();
}

TonemapPass::~TonemapPass() = default;

const Frame& TonemapPass::frame() const { return impl_->frame; }

DisplayImage TonemapPass::render() {
    auto t0 = std::chrono::steady_clock::now();
    impl_->ctx.submitAndWait([&](VkCommandBuffer cmd) { recordFrame(cmd, impl_->frame); });
    DisplayImage img = impl_->read();
    lastMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return img;
}

}  // namespace metamer
