#include "render/spectral_pass.h"

#include "interface.h"
#include "render/camera_matrices.h"

#include "spectral.frag.1.spv.h"
#include "spectral.frag.2.spv.h"
#include "spectral.frag.3.spv.h"
#include "spectral.frag.4.spv.h"
#include "spectral.frag.5.spv.h"
#include "spectral.frag.6.spv.h"
#include "spectral.frag.7.spv.h"
#include "spectral.frag.8.spv.h"
#include "spectral.vert.spv.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>

namespace metamer {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

struct Draw {
    uint32_t firstIndex, indexCount;
    int32_t vertexOffset;
    uint32_t material;
};

// Everything the fragment shader reads, packed for the three storage buffers of interface.h.
struct PackedScene {
    std::vector<float> vertices;  // position xyz, normal xyz
    std::vector<uint32_t> indices;
    std::vector<Draw> draws;
    std::vector<gpu::GpuLight> lights;
    std::vector<gpu::GpuMaterial> materials;
    std::vector<float> spectra;
};

uint32_t append(std::vector<float>& table, const std::vector<double>& values) {
    uint32_t offset = uint32_t(table.size());
    for (double v : values) table.push_back(float(v));
    return offset;
}

PackedScene pack(const Scene& scene, const SceneOnGrid& g) {
    PackedScene p;
    for (const auto& mesh : scene.meshes) {
        if (mesh.indices.empty()) continue;
        Draw d{uint32_t(p.indices.size()), uint32_t(mesh.indices.size()), int32_t(p.vertices.size() / 6),
               mesh.material};
        for (size_t i = 0; i < mesh.positions.size(); ++i) {
            for (int k = 0; k < 3; ++k) p.vertices.push_back(float(mesh.positions[i][k]));
            for (int k = 0; k < 3; ++k) p.vertices.push_back(float(mesh.normals[i][k]));
        }
        p.indices.insert(p.indices.end(), mesh.indices.begin(), mesh.indices.end());
        p.draws.push_back(d);
    }
    for (size_t l = 0; l < scene.lights.size(); ++l) {
        const Light& light = scene.lights[l];
        gpu::GpuLight gl{};
        switch (light.type) {
            case Light::Type::Ambient: gl.type = LIGHT_AMBIENT; break;
            case Light::Type::Directional:
                gl.type = LIGHT_DIRECTIONAL;
                gl.vector = glm::vec4(glm::vec3(-glm::normalize(light.direction)), 0.0f);
                break;
            case Light::Type::Point:
                gl.type = LIGHT_POINT;
                gl.vector = glm::vec4(glm::vec3(light.position), 1.0f);
                break;
        }
        gl.spectrumOffset = append(p.spectra, g.lights[l]);
        p.lights.push_back(gl);
    }
    // View-independent fluorescence coupling per (material, light): (Φ/π)·Σ a·E_l·λ·Δλ, in
    // double, so the shader only multiplies by the light's geometric factor.
    std::vector<double> emissionOverLambda;
    for (const auto& m : g.materials) {
        gpu::GpuMaterial gm{};
        gm.gloss = float(m.gloss);
        gm.diffuseOffset = append(p.spectra, m.diffuse);
        gm.specularOffset = append(p.spectra, m.specular);
        gm.hasSpecular = std::any_of(m.specular.begin(), m.specular.end(), [](double v) { return v != 0.0; });
        if (m.fluorescent) {
            gm.fluorescent = 1;
            emissionOverLambda.resize(m.emission.size());
            for (size_t i = 0; i < m.emission.size(); ++i)
                emissionOverLambda[i] = m.emission[i] / g.wavelengths_nm[i];
            gm.emissionOffset = append(p.spectra, emissionOverLambda);
            std::vector<double> coupling;
            for (const auto& E : g.lights) {
                double s = 0.0;
                for (size_t i = 0; i < E.size(); ++i) s += m.excitation[i] * E[i] * g.wavelengths_nm[i];
                coupling.push_back(m.quantum_yield / M_PI * s * g.grid.step_nm);
            }
            gm.couplingOffset = append(p.spectra, coupling);
        }
        p.materials.push_back(gm);
    }
    return p;
}

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

VkShaderModule makeShader(VkDevice device, const uint32_t* code, size_t bytes) {
    VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    ci.codeSize = bytes;
    ci.pCode = code;
    VkShaderModule m;
    VK_CHECK(vkCreateShaderModule(device, &ci, nullptr, &m));
    return m;
}

}  // namespace

std::string SpectralPassPlan::describe() const {
    return fmt::format("{} bands in {} RGBA32F layers, {} pass(es) of ≤{} attachments, {}×{} target ({} MiB), "
                       "{} light(s), specular {}, fluorescence {}, ssaa {}, readback by {}",
                       bands, layers, passes, MAX_OUTPUTS, targetWidth, targetHeight, targetBytes >> 20,
                       lightCount, hasSpecular ? "on" : "off", hasFluorescence ? "on" : "off", ssaa,
                       mappedReadback ? "mapping a linear image" : "copy");
}

struct SpectralPass::Impl {
    vk::Context& ctx;
    const Scene& scene;
    Grid grid;
    SpectralPassPlan plan;
    PackedScene packed;
    CameraMatrices camera;

    vk::Buffer vertexBuffer, indexBuffer, lightBuffer, materialBuffer, spectraBuffer, readbackBuffer;
    vk::Image color, depth;
    VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
    VkPipelineLayout pipelineLayout = VK_NULL_HANDLE;
    VkDescriptorPool descriptorPool = VK_NULL_HANDLE;
    VkDescriptorSet descriptorSet = VK_NULL_HANDLE;
    VkShaderModule vert = VK_NULL_HANDLE;
    struct PassObjects {
        uint32_t firstLayer = 0, attachments = 0;
        VkRenderPass renderPass = VK_NULL_HANDLE;
        VkPipeline pipeline = VK_NULL_HANDLE;
        VkFramebuffer framebuffer = VK_NULL_HANDLE;
    };
    std::vector<PassObjects> passes;

    Impl(vk::Context& c, const Scene& s) : ctx(c), scene(s) {}
    ~Impl() {
        VkDevice d = ctx.device();
        for (auto& p : passes) {
            if (p.framebuffer) vkDestroyFramebuffer(d, p.framebuffer, nullptr);
            if (p.pipeline) vkDestroyPipeline(d, p.pipeline, nullptr);
            if (p.renderPass) vkDestroyRenderPass(d, p.renderPass, nullptr);
        }
        if (vert) vkDestroyShaderModule(d, vert, nullptr);
        if (descriptorPool) vkDestroyDescriptorPool(d, descriptorPool, nullptr);
        if (pipelineLayout) vkDestroyPipelineLayout(d, pipelineLayout, nullptr);
        if (setLayout) vkDestroyDescriptorSetLayout(d, setLayout, nullptr);
    }

    vk::Buffer storage(const void* data, size_t bytes, const char* name) {
        // Vulkan forbids empty buffers; a scene without lights still binds one.
        vk::Buffer b(ctx, std::max<size_t>(bytes, 64), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, name);
        if (bytes) b.upload(data, bytes);
        return b;
    }

    void createBuffers() {
        if (!packed.vertices.empty()) {
            vertexBuffer = vk::Buffer(ctx, packed.vertices.size() * 4, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, "vertices");
            vertexBuffer.upload(packed.vertices.data(), packed.vertices.size() * 4);
            indexBuffer = vk::Buffer(ctx, packed.indices.size() * 4, VK_BUFFER_USAGE_INDEX_BUFFER_BIT, "indices");
            indexBuffer.upload(packed.indices.data(), packed.indices.size() * 4);
        }
        lightBuffer = storage(packed.lights.data(), packed.lights.size() * sizeof(gpu::GpuLight), "lights");
        materialBuffer =
            storage(packed.materials.data(), packed.materials.size() * sizeof(gpu::GpuMaterial), "materials");
        spectraBuffer = storage(packed.spectra.data(), packed.spectra.size() * 4, "spectra");
    }

    void createTargets(Readback mode) {
        uint32_t w = plan.targetWidth, h = plan.targetHeight, layers = uint32_t(plan.layers);
        bool tryMap = mode != Readback::Copy &&
                      vk::supportsLinearRenderTarget(ctx, VK_FORMAT_R32G32B32A32_SFLOAT, w, h, layers);
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
            cd.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
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
            cd.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
            cd.hostVisible = false;
            color = vk::Image(ctx, cd);
            plan.mappedReadback = false;
            readbackBuffer = vk::Buffer(ctx, plan.targetBytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, "readback");
        }
        vk::ImageDesc dd;
        dd.format = VK_FORMAT_D32_SFLOAT;
        dd.width = w;
        dd.height = h;
        dd.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
        dd.name = "depth";
        depth = vk::Image(ctx, dd);
    }

    void createLayouts() {
        VkDevice d = ctx.device();
        VkDescriptorSetLayoutBinding bindings[3];
        uint32_t ids[3] = {BINDING_LIGHTS, BINDING_MATERIALS, BINDING_SPECTRA};
        for (int i = 0; i < 3; ++i)
            bindings[i] = {ids[i], VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr};
        VkDescriptorSetLayoutCreateInfo sl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        sl.bindingCount = 3;
        sl.pBindings = bindings;
        VK_CHECK(vkCreateDescriptorSetLayout(d, &sl, nullptr, &setLayout));
        VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                                  sizeof(gpu::SpectralPushConstants)};
        VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        pl.setLayoutCount = 1;
        pl.pSetLayouts = &setLayout;
        pl.pushConstantRangeCount = 1;
        pl.pPushConstantRanges = &range;
        VK_CHECK(vkCreatePipelineLayout(d, &pl, nullptr, &pipelineLayout));

        VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 3};
        VkDescriptorPoolCreateInfo pci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        pci.maxSets = 1;
        pci.poolSizeCount = 1;
        pci.pPoolSizes = &size;
        VK_CHECK(vkCreateDescriptorPool(d, &pci, nullptr, &descriptorPool));
        VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        ai.descriptorPool = descriptorPool;
        ai.descriptorSetCount = 1;
        ai.pSetLayouts = &setLayout;
        VK_CHECK(vkAllocateDescriptorSets(d, &ai, &descriptorSet));
        VkDescriptorBufferInfo infos[3] = {{lightBuffer.handle(), 0, VK_WHOLE_SIZE},
                                           {materialBuffer.handle(), 0, VK_WHOLE_SIZE},
                                           {spectraBuffer.handle(), 0, VK_WHOLE_SIZE}};
        VkWriteDescriptorSet writes[3];
        for (int i = 0; i < 3; ++i) {
            writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
            writes[i].dstSet = descriptorSet;
            writes[i].dstBinding = ids[i];
            writes[i].descriptorCount = 1;
            writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
            writes[i].pBufferInfo = &infos[i];
        }
        vkUpdateDescriptorSets(d, 3, writes, 0, nullptr);

        vert = makeShader(d, kSpirv_spectral_vert, sizeof(kSpirv_spectral_vert));
    }

    VkRenderPass makeRenderPass(uint32_t attachments) {
        std::vector<VkAttachmentDescription> descs;
        std::vector<VkAttachmentReference> refs;
        VkImageLayout finalLayout =
            plan.mappedReadback ? VK_IMAGE_LAYOUT_GENERAL : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        for (uint32_t i = 0; i < attachments; ++i) {
            VkAttachmentDescription a{};
            a.format = VK_FORMAT_R32G32B32A32_SFLOAT;
            a.samples = VK_SAMPLE_COUNT_1_BIT;
            a.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
            a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
            a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
            a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
            a.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
            a.finalLayout = finalLayout;
            descs.push_back(a);
            refs.push_back({i, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL});
        }
        VkAttachmentDescription da{};
        da.format = VK_FORMAT_D32_SFLOAT;
        da.samples = VK_SAMPLE_COUNT_1_BIT;
        da.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        da.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        da.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
        da.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        da.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        da.finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        descs.push_back(da);
        VkAttachmentReference depthRef{attachments, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};

        VkSubpassDescription sub{};
        sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
        sub.colorAttachmentCount = attachments;
        sub.pColorAttachments = refs.data();
        sub.pDepthStencilAttachment = &depthRef;
        // The depth image is reused by every pass: wait for the previous pass's depth writes.
        VkSubpassDependency dep{};
        dep.srcSubpass = VK_SUBPASS_EXTERNAL;
        dep.dstSubpass = 0;
        dep.srcStageMask = VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
        dep.dstStageMask = VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
        dep.srcAccessMask = VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
        dep.dstAccessMask = VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
        VkRenderPassCreateInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
        rp.attachmentCount = uint32_t(descs.size());
        rp.pAttachments = descs.data();
        rp.subpassCount = 1;
        rp.pSubpasses = &sub;
        rp.dependencyCount = 1;
        rp.pDependencies = &dep;
        VkRenderPass r;
        VK_CHECK(vkCreateRenderPass(ctx.device(), &rp, nullptr, &r));
        return r;
    }

    VkPipeline makePipeline(VkRenderPass renderPass, uint32_t attachments) {
        struct Spec {
            int32_t lightCount, bandCount;
            VkBool32 hasSpecular, hasFluorescence;
        } spec{plan.lightCount, plan.bands, plan.hasSpecular, plan.hasFluorescence};
        VkSpecializationMapEntry entries[4] = {
            {SPEC_LIGHT_COUNT, offsetof(Spec, lightCount), 4},
            {SPEC_BAND_COUNT, offsetof(Spec, bandCount), 4},
            {SPEC_HAS_SPECULAR, offsetof(Spec, hasSpecular), 4},
            {SPEC_HAS_FLUORESCENCE, offsetof(Spec, hasFluorescence), 4},
        };
        VkSpecializationInfo si{4, entries, sizeof(Spec), &spec};
        const SpirvCode& fragCode = kSpectralFrag[attachments - 1];
        VkShaderModule frag = makeShader(ctx.device(), fragCode.code, fragCode.bytes);
        VkPipelineShaderStageCreateInfo stages[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                                     {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
        stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
        stages[0].module = vert;
        stages[0].pName = "main";
        stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
        stages[1].module = frag;
        stages[1].pName = "main";
        stages[1].pSpecializationInfo = &si;

        VkVertexInputBindingDescription binding{0, 6 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX};
        VkVertexInputAttributeDescription attrs[2] = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                                                      {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 3 * sizeof(float)}};
        VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
        vi.vertexBindingDescriptionCount = 1;
        vi.pVertexBindingDescriptions = &binding;
        vi.vertexAttributeDescriptionCount = 2;
        vi.pVertexAttributeDescriptions = attrs;
        VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
        ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
        VkViewport viewport{0, 0, float(plan.targetWidth), float(plan.targetHeight), 0, 1};
        VkRect2D scissor{{0, 0}, {plan.targetWidth, plan.targetHeight}};
        VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
        vp.viewportCount = 1;
        vp.pViewports = &viewport;
        vp.scissorCount = 1;
        vp.pScissors = &scissor;
        VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
        rs.polygonMode = VK_POLYGON_MODE_FILL;
        rs.cullMode = VK_CULL_MODE_NONE;  // two-sided shading: back faces are visible
        // Front faces are counter-clockwise seen from their normal side (scene/scene.h). Vulkan
        // judges winding in y-down framebuffer space; the projection's y flip cancels that.
        rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
        rs.lineWidth = 1.0f;
        VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
        ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
        VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
        ds.depthTestEnable = VK_TRUE;
        ds.depthWriteEnable = VK_TRUE;
        ds.depthCompareOp = VK_COMPARE_OP_LESS;
        std::vector<VkPipelineColorBlendAttachmentState> blends(attachments);
        for (auto& b : blends) {
            b = {};
            b.colorWriteMask = 0xF;
        }
        VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
        cb.attachmentCount = attachments;
        cb.pAttachments = blends.data();
        VkGraphicsPipelineCreateInfo gp{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
        gp.stageCount = 2;
        gp.pStages = stages;
        gp.pVertexInputState = &vi;
        gp.pInputAssemblyState = &ia;
        gp.pViewportState = &vp;
        gp.pRasterizationState = &rs;
        gp.pMultisampleState = &ms;
        gp.pDepthStencilState = &ds;
        gp.pColorBlendState = &cb;
        gp.layout = pipelineLayout;
        gp.renderPass = renderPass;
        VkPipeline p;
        VkResult r = vkCreateGraphicsPipelines(ctx.device(), VK_NULL_HANDLE, 1, &gp, nullptr, &p);
        vkDestroyShaderModule(ctx.device(), frag, nullptr);  // the pipeline keeps what it needs
        VK_CHECK(r);
        return p;
    }

    void createPasses() {
        // One render pass + pipeline per distinct attachment count (at most two: 8 and the rest).
        VkRenderPass rpFull = VK_NULL_HANDLE, rpLast = VK_NULL_HANDLE;
        VkPipeline plFull = VK_NULL_HANDLE, plLast = VK_NULL_HANDLE;
        for (int p = 0; p < plan.passes; ++p) {
            PassObjects po;
            po.firstLayer = uint32_t(p * MAX_OUTPUTS);
            po.attachments = std::min<uint32_t>(MAX_OUTPUTS, uint32_t(plan.layers) - po.firstLayer);
            bool full = po.attachments == MAX_OUTPUTS;
            VkRenderPass& rp = full ? rpFull : rpLast;
            VkPipeline& pl = full ? plFull : plLast;
            bool owner = rp == VK_NULL_HANDLE;
            if (owner) {
                rp = makeRenderPass(po.attachments);
                pl = makePipeline(rp, po.attachments);
            }
            // Only the first pass using a render pass/pipeline owns it (destroyed once).
            po.renderPass = owner ? rp : VK_NULL_HANDLE;
            po.pipeline = owner ? pl : VK_NULL_HANDLE;
            std::vector<VkImageView> views;
            for (uint32_t i = 0; i < po.attachments; ++i) views.push_back(color.layerView(po.firstLayer + i));
            views.push_back(depth.layerView(0));
            VkFramebufferCreateInfo fb{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
            fb.renderPass = rp;
            fb.attachmentCount = uint32_t(views.size());
            fb.pAttachments = views.data();
            fb.width = plan.targetWidth;
            fb.height = plan.targetHeight;
            fb.layers = 1;
            VK_CHECK(vkCreateFramebuffer(ctx.device(), &fb, nullptr, &po.framebuffer));
            passes.push_back(po);
            passRenderPass.push_back(rp);
            passPipeline.push_back(pl);
        }
    }
    std::vector<VkRenderPass> passRenderPass;
    std::vector<VkPipeline> passPipeline;

    void record(VkCommandBuffer cmd) {
        gpu::SpectralPushConstants pc{};
        pc.viewProjection = camera.viewProjection;
        pc.cameraPosition = glm::vec4(camera.position, camera.perspective ? 1.0f : 0.0f);
        pc.cameraForward = glm::vec4(camera.forward, 0.0f);
        for (size_t p = 0; p < passes.size(); ++p) {
            const PassObjects& po = passes[p];
            std::vector<VkClearValue> clears(po.attachments + 1);
            for (uint32_t i = 0; i < po.attachments; ++i) clears[i].color = {{0, 0, 0, 0}};
            clears[po.attachments].depthStencil = {1.0f, 0};
            VkRenderPassBeginInfo rb{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
            rb.renderPass = passRenderPass[p];
            rb.framebuffer = po.framebuffer;
            rb.renderArea = {{0, 0}, {plan.targetWidth, plan.targetHeight}};
            rb.clearValueCount = uint32_t(clears.size());
            rb.pClearValues = clears.data();
            vkCmdBeginRenderPass(cmd, &rb, VK_SUBPASS_CONTENTS_INLINE);
            if (!packed.draws.empty()) {
                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, passPipeline[p]);
                vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelineLayout, 0, 1, &descriptorSet,
                                        0, nullptr);
                VkDeviceSize zero = 0;
                VkBuffer vb = vertexBuffer.handle();
                vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &zero);
                vkCmdBindIndexBuffer(cmd, indexBuffer.handle(), 0, VK_INDEX_TYPE_UINT32);
                pc.firstLayer = po.firstLayer;
                for (const Draw& d : packed.draws) {
                    pc.materialIndex = d.material;
                    vkCmdPushConstants(cmd, pipelineLayout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                                       0, sizeof(pc), &pc);
                    vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
                }
            }
            vkCmdEndRenderPass(cmd);
        }
        if (plan.mappedReadback) {
            // Make the colour writes visible to the host, which reads the linear image directly.
            VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
            b.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
            b.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
            b.oldLayout = VK_IMAGE_LAYOUT_GENERAL;
            b.newLayout = VK_IMAGE_LAYOUT_GENERAL;
            b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            b.image = color.handle();
            b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, uint32_t(plan.layers)};
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0,
                                 0, nullptr, 0, nullptr, 1, &b);
        } else {
            VkBufferImageCopy region{};
            region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, uint32_t(plan.layers)};
            region.imageExtent = {plan.targetWidth, plan.targetHeight, 1};
            vkCmdCopyImageToBuffer(cmd, color.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readbackBuffer.handle(),
                                   1, &region);
            VkBufferMemoryBarrier b{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
            b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            b.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
            b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            b.buffer = readbackBuffer.handle();
            b.size = VK_WHOLE_SIZE;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 0, nullptr, 1, &b,
                                 0, nullptr);
        }
    }

    // Layer l, row y of the target: 4 floats per pixel.
    struct LayerAccess {
        const char* base;
        size_t rowPitch, layerPitch;
        const float* row(uint32_t layer, uint32_t y) const {
            return reinterpret_cast<const float*>(base + layer * layerPitch + y * rowPitch);
        }
    };

    LayerAccess access() {
        LayerAccess a{};
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

    // Layered target → pixel-interleaved cube, box-filtering ssaa×ssaa samples; rows in parallel.
    void readInto(SpectralCube& cube) {
        LayerAccess a = access();
        int s = plan.ssaa, bands = plan.bands, W = cube.width, H = cube.height;
        float norm = 1.0f / float(s * s);
        auto work = [&](int y0, int y1) {
            std::vector<float> acc(size_t(W) * plan.layers * 4);
            for (int y = y0; y < y1; ++y) {
                std::fill(acc.begin(), acc.end(), 0.0f);
                for (int l = 0; l < plan.layers; ++l)
                    for (int sy = 0; sy < s; ++sy) {
                        const float* row = a.row(uint32_t(l), uint32_t(y * s + sy));
                        for (int x = 0; x < W; ++x)
                            for (int sx = 0; sx < s; ++sx)
                                for (int c = 0; c < 4; ++c)
                                    acc[(size_t(x) * plan.layers + l) * 4 + c] += row[(x * s + sx) * 4 + c];
                    }
                for (int x = 0; x < W; ++x) {
                    float* out = cube.pixel(x, y);
                    const float* in = &acc[size_t(x) * plan.layers * 4];
                    for (int b = 0; b < bands; ++b) out[b] = s == 1 ? in[b] : in[b] * norm;
                }
            }
        };
        int threads = std::max(1, std::min<int>(int(std::thread::hardware_concurrency()), H));
        std::vector<std::thread> pool;
        for (int t = 0; t < threads; ++t) pool.emplace_back(work, H * t / threads, H * (t + 1) / threads);
        for (auto& t : pool) t.join();
    }
};

SpectralPass::SpectralPass(vk::Context& ctx, const Scene& scene, const SceneOnGrid& spectra,
                           const SpectralPassOptions& options)
    : impl_(std::make_unique<Impl>(ctx, scene)) {
    auto t0 = Clock::now();
    if (options.ssaa < 1 || options.ssaa > 4)
        failInput(Where{"", "--ssaa"}, "supersampling must be 1, 2, 3 or 4 (samples per pixel side), got {}",
                  options.ssaa);
    SpectralPassPlan& p = plan_;
    p.bands = spectra.grid.bands();
    p.layers = spectra.grid.layers();
    p.passes = (p.layers + MAX_OUTPUTS - 1) / MAX_OUTPUTS;
    p.lightCount = int(scene.lights.size());
    p.hasSpecular = scene.hasSpecular();
    p.hasFluorescence = scene.hasFluorescence();
    p.ssaa = options.ssaa;
    p.targetWidth = uint32_t(scene.camera.width * options.ssaa);
    p.targetHeight = uint32_t(scene.camera.height * options.ssaa);
    p.targetBytes = size_t(p.targetWidth) * p.targetHeight * p.layers * 16;
    uint32_t maxDim = ctx.properties().limits.maxFramebufferWidth;
    if (p.targetWidth > maxDim || p.targetHeight > ctx.properties().limits.maxFramebufferHeight)
        failInput(Where{"", "camera"}, "render target {}×{} exceeds the device limit {}×{}", p.targetWidth,
                  p.targetHeight, maxDim, ctx.properties().limits.maxFramebufferHeight);

    Impl& m = *impl_;
    m.plan = p;
    m.grid = spectra.grid;
    m.packed = pack(scene, spectra);
    m.camera = cameraMatrices(scene.camera, scene);
    m.createBuffers();
    m.createTargets(options.readback);
    m.createLayouts();
    m.createPasses();
    plan_ = m.plan;
    timings_.upload_ms = msSince(t0);
}

SpectralPass::~SpectralPass() = default;

SpectralCube SpectralPass::render() {
    Impl& m = *impl_;
    auto t0 = Clock::now();
    m.ctx.submitAndWait([&](VkCommandBuffer cmd) { m.record(cmd); });
    timings_.shading_ms = msSince(t0);
    auto t1 = Clock::now();
    SpectralCube cube(m.scene.camera.width, m.scene.camera.height, m.grid);
    m.readInto(cube);
    timings_.readback_ms = msSince(t1);
    return cube;
}

}  // namespace metamer
