#include "render/spectral_pass.h"

#include "interface.h"
#include "render/camera_matrices.h"
#include "vk/pipeline.h"

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
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
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

// Everything the fragment shader reads, packed per pass for the uniform blocks of interface.h.
struct PackedScene {
    std::vector<float> vertices;  // VERTEX_FLOATS each: position xyz, normal xyz, uv, tangent xyzw
    std::vector<uint32_t> indices;
    std::vector<Draw> draws;
    int ambient = 0, directional = 0, point = 0;  // light counts, in this order in every block
    gpu::GpuLightBlock lights{};
    std::vector<gpu::GpuLightSpectraBlock> lightSpectra;  // per pass
    std::vector<gpu::GpuMaterialBlock> materials;         // per pass × material: [pass][material]
    // Fluorescence as per-light spectra (scenes with a Donaldson matrix; interface.h,
    // GpuFluorescenceBlock): records of lightSlots × MAX_OUTPUTS vec4; per pass, record 0 is zeros
    // (non-fluorescent materials, and the only record when fluorescenceSpectra is false) and record
    // 1 + j the j-th fluorescent material's. [pass][record][light][k].
    bool fluorescenceSpectra = false;
    int lightSlots = 1;  // max(1, light count)
    int fluorescenceRecords = 1;                  // per pass
    std::vector<uint32_t> fluorescenceRecord;     // per material: its record in every pass
    std::vector<glm::vec4> fluorescence;
};

// Band b of pass p lives at vec4 k = (b - 32p) / 4, component (b - 32p) % 4; bands past the grid are 0.
void scatterBands(const std::vector<double>& values, int pass, glm::vec4* dst) {
    for (int k = 0; k < MAX_OUTPUTS; ++k)
        for (int c = 0; c < 4; ++c) {
            size_t b = size_t(pass) * BANDS_PER_PASS + size_t(k) * 4 + c;
            dst[k][c] = b < values.size() ? float(values[b]) : 0.0f;
        }
}

void packFluorescence(PackedScene& p, const Scene& scene, const SceneOnGrid& g, const std::vector<size_t>& order,
                      int passes);

PackedScene pack(const Scene& scene, const SceneOnGrid& g, int passes) {
    checkMeshes(scene);  // the vertex and index arrays below are read as they promise
    PackedScene p;
    for (const auto& mesh : scene.meshes) {
        if (mesh.indices.empty()) continue;
        Draw d{uint32_t(p.indices.size()), uint32_t(mesh.indices.size()),
               int32_t(p.vertices.size() / VERTEX_FLOATS), mesh.material};
        auto vertex = [&p, &mesh](uint32_t i, const glm::dvec3& normal) {
            glm::dvec2 uv = mesh.uvs.empty() ? glm::dvec2(0.0) : mesh.uvs[i];
            glm::dvec4 t = mesh.tangents.empty() ? glm::dvec4(0.0) : mesh.tangents[i];
            for (int k = 0; k < 3; ++k) p.vertices.push_back(float(mesh.positions[i][k]));
            for (int k = 0; k < 3; ++k) p.vertices.push_back(float(normal[k]));
            for (int k = 0; k < 2; ++k) p.vertices.push_back(float(uv[k]));
            for (int k = 0; k < 4; ++k) p.vertices.push_back(float(t[k]));
        };
        // Normals of (nearly) zero length, or none at all, are allowed by the model: the reference
        // then shades with the face normal (docs/physics.md, "Two-sided shading"). A triangle
        // with no usable normal at any corner gets its own three vertices carrying the face
        // normal, computed here in double; spectral.frag falls back to a screen-space face normal
        // only where usable normals cancel, which is less precise (~1e-5 rad).
        const bool hasNormals = mesh.normals.size() == mesh.positions.size();
        auto usable = [&](uint32_t i) { return hasNormals && glm::length(mesh.normals[i]) > 1e-12; };
        for (size_t i = 0; i < mesh.positions.size(); ++i)
            vertex(uint32_t(i), hasNormals ? mesh.normals[i] : glm::dvec3(0.0));
        uint32_t next = uint32_t(mesh.positions.size());
        for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
            const uint32_t* tri = &mesh.indices[t];
            if (usable(tri[0]) || usable(tri[1]) || usable(tri[2])) {
                p.indices.insert(p.indices.end(), tri, tri + 3);
                continue;
            }
            const glm::dvec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]], &c = mesh.positions[tri[2]];
            glm::dvec3 face = glm::cross(b - a, c - a);
            const double len = glm::length(face);
            face = len > 0.0 ? face / len : glm::dvec3(0.0);  // zero area: never rasterized
            for (int k = 0; k < 3; ++k) {
                vertex(tri[k], face);
                p.indices.push_back(next++);
            }
        }
        d.indexCount = uint32_t(p.indices.size()) - d.firstIndex;
        p.draws.push_back(d);
    }
    // Lights sorted by kind (the shader loops over each kind without branching).
    std::vector<size_t> order;
    for (Light::Type type : {Light::Type::Ambient, Light::Type::Directional, Light::Type::Point})
        for (size_t l = 0; l < scene.lights.size(); ++l)
            if (scene.lights[l].type == type) {
                order.push_back(l);
                (type == Light::Type::Ambient ? p.ambient : type == Light::Type::Directional ? p.directional : p.point)++;
            }
    for (size_t i = 0; i < order.size(); ++i) {
        const Light& light = scene.lights[order[i]];
        if (light.type == Light::Type::Directional)
            p.lights.lights[i].vector = glm::vec4(glm::vec3(-glm::normalize(light.direction)), 0.0f);
        else if (light.type == Light::Type::Point)
            p.lights.lights[i].vector = glm::vec4(glm::vec3(light.position), 1.0f);
    }
    // The shader holds E(λ) in float32: beyond its largest value E would become +Inf, and Inf × 0
    // (a black band, a light behind the surface) NaN. Refused rather than rendered wrong.
    for (size_t l = 0; l < scene.lights.size(); ++l)
        for (size_t b = 0; b < g.lights[l].size(); ++b)
            if (std::fabs(g.lights[l][b]) > double(std::numeric_limits<float>::max()))
                failInput(scene.lights[l].spectrum.where,
                          "light spectrum '{}' × scale {:g} is {:g} at {:g} nm, beyond the largest float32 ({:g}) "
                          "the GPU path computes with",
                          scene.lights[l].spectrum.spectrum.source, scene.lights[l].scale, g.lights[l][b],
                          g.wavelengths_nm[b], double(std::numeric_limits<float>::max()));
    p.lightSpectra.resize(passes);
    for (int pass = 0; pass < passes; ++pass)
        for (size_t i = 0; i < order.size(); ++i)
            scatterBands(g.lights[order[i]], pass, &p.lightSpectra[pass].lightBands[i * MAX_OUTPUTS]);

    // A Donaldson matrix does not factor into a coupling × a shape: a scene with one renders every
    // fluorescent material from per-light spectra; other scenes keep the cheaper rank-one form.
    p.fluorescenceSpectra = std::any_of(g.materials.begin(), g.materials.end(),
                                        [](const MaterialOnGrid& m) { return m.fluorescent && m.isMatrix(); });
    p.materials.resize(size_t(passes) * g.materials.size());
    std::vector<double> emissionOverLambda;
    for (size_t mi = 0; mi < g.materials.size(); ++mi) {
        const MaterialOnGrid& m = g.materials[mi];
        bool specular = std::any_of(m.specular.begin(), m.specular.end(), [](double v) { return v != 0.0; });
        // View-independent fluorescence coupling per light, (Φ/π)·Σ a·E_l·λ·Δλ, summed in double
        // so the shader only multiplies by the light's geometric factor.
        std::vector<float> coupling(MAX_LIGHTS, 0.0f);
        emissionOverLambda.assign(m.diffuse.size(), 0.0);
        if (m.fluorescent && !p.fluorescenceSpectra) {
            double largest = 0.0;
            for (size_t i = 0; i < m.emission.size(); ++i) {
                emissionOverLambda[i] = m.emission[i] / g.wavelengths_nm[i];
                largest = std::max(largest, emissionOverLambda[i]);
            }
            // The coupling is the radiance over ê/λ (~1e-5 nm⁻² for a dye), so in float32 it would
            // overflow ~1e5 times sooner than the radiance does (at a light scale of ~1e35).
            // Moving a power of two from ê/λ into it keeps both near the radiance's magnitude and
            // leaves their product the same bit for bit.
            const int shift = largest > 0.0 ? std::ilogb(largest) : 0;
            for (double& v : emissionOverLambda) v = std::ldexp(v, -shift);
            for (size_t i = 0; i < order.size(); ++i) {
                const auto& E = g.lights[order[i]];
                double sum = 0.0;
                for (size_t b = 0; b < E.size(); ++b) sum += m.excitation[b] * E[b] * g.wavelengths_nm[b];
                coupling[i] = float(std::ldexp(m.quantum_yield / M_PI * sum * g.grid.step_nm, shift));
            }
        }
        for (int pass = 0; pass < passes; ++pass) {
            gpu::GpuMaterialBlock& b = p.materials[size_t(pass) * g.materials.size() + mi];
            scatterBands(m.diffuse, pass, b.diffuse);
            scatterBands(m.specular, pass, b.specular);
            scatterBands(emissionOverLambda, pass, b.emissionOverLambda);
            b.params = glm::vec4(float(m.gloss), m.fluorescent ? 1.0f : 0.0f, specular ? 1.0f : 0.0f, 0.0f);
            b.textures = glm::vec4(m.diffuseTexture >= 0 ? 1.0f : 0.0f, m.specularTexture >= 0 ? 1.0f : 0.0f,
                                   m.normalTexture >= 0 ? 1.0f : 0.0f, float(pass * MAX_OUTPUTS));
            for (int l = 0; l < MAX_LIGHTS; ++l) b.coupling[l / 4][l % 4] = coupling[l];
        }
    }
    packFluorescence(p, scene, g, order, passes);
    return p;
}

// The fluorescent radiance per unit geometric factor of every fluorescent material under every
// light, F_l(λo) = (1/π)·Σᵢ D(λᵢ, λo)·E_l(λᵢ)·Δλ, in double, then rounded once to float. The
// rank-one form is the matrix D = Φ·a(λᵢ)·ê(λo)·λᵢ/λo, which factors the sum:
// F_l(λo) = (Φ/π)·ê(λo)/λo·Σᵢ a·E_l·λᵢ·Δλ. F is a radiance (× d² for a point light), so it is no
// nearer float32's limits than the image itself; a value beyond them is refused, as a light is.
void packFluorescence(PackedScene& p, const Scene& scene, const SceneOnGrid& g, const std::vector<size_t>& order,
                      int passes) {
    const size_t n = g.wavelengths_nm.size(), lights = order.size();
    const double step = g.grid.step_nm;
    p.lightSlots = std::max<int>(1, int(lights));
    p.fluorescenceRecord.assign(g.materials.size(), 0);
    std::vector<std::vector<double>> emitted;  // per fluorescent material: [light][band]
    for (size_t mi = 0; mi < g.materials.size(); ++mi) {
        const MaterialOnGrid& m = g.materials[mi];
        if (!m.fluorescent || !p.fluorescenceSpectra) continue;
        p.fluorescenceRecord[mi] = uint32_t(emitted.size() + 1);
        std::vector<double> f(lights * n, 0.0);
        for (size_t i = 0; i < lights; ++i) {
            const std::vector<double>& E = g.lights[order[i]];
            double* out = &f[i * n];
            if (m.isMatrix()) {
                for (size_t in = 0; in < n; ++in) {
                    const double e = E[in] * step / M_PI;
                    if (e == 0.0) continue;
                    const double* row = &m.donaldson[in * n];
                    for (size_t o = 0; o < n; ++o) out[o] += row[o] * e;
                }
            } else {
                double absorbed = 0.0;  // Σ a·E·λ·Δλ
                for (size_t b = 0; b < n; ++b) absorbed += m.excitation[b] * E[b] * g.wavelengths_nm[b] * step;
                for (size_t o = 0; o < n; ++o)
                    out[o] = m.quantum_yield / M_PI * m.emission[o] / g.wavelengths_nm[o] * absorbed;
            }
            for (size_t o = 0; o < n; ++o)
                if (!(std::fabs(out[o]) <= double(std::numeric_limits<float>::max()))) {
                    const Fluorescence& fl = *scene.materials[mi].fluorescence;
                    failInput(fl.matrix ? fl.matrix->where : fl.excitation.where,
                              "the fluorescence of material '{}' under {} is {:g} W·sr⁻¹·m⁻²·nm⁻¹ per unit geometric "
                              "factor at {:g} nm, beyond the largest float32 ({:g}) the GPU path computes with",
                              scene.materials[mi].name, scene.lights[order[i]].name, out[o], g.wavelengths_nm[o],
                              double(std::numeric_limits<float>::max()));
                }
        }
        emitted.push_back(std::move(f));
    }
    p.fluorescenceRecords = int(emitted.size()) + 1;
    const size_t recordVec4 = size_t(p.lightSlots) * MAX_OUTPUTS;
    if (!p.fluorescenceSpectra) {  // never read: one record of zeros for the binding
        p.fluorescence.assign(recordVec4, glm::vec4(0.0f));
        return;
    }
    p.fluorescence.assign(size_t(passes) * p.fluorescenceRecords * recordVec4, glm::vec4(0.0f));
    std::vector<double> bands(n);
    for (int pass = 0; pass < passes; ++pass)
        for (size_t r = 1; r < size_t(p.fluorescenceRecords); ++r)
            for (size_t i = 0; i < lights; ++i) {
                const double* src = &emitted[r - 1][i * n];
                bands.assign(src, src + n);
                glm::vec4* dst = &p.fluorescence[((size_t(pass) * p.fluorescenceRecords + r) * p.lightSlots + i) * MAX_OUTPUTS];
                scatterBands(bands, pass, dst);
            }
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


}  // namespace

std::string SpectralPassPlan::describe() const {
    return fmt::format("{} bands in {} RGBA32F layers, a depth pre-pass + {} colour pass(es) of ≤{} attachments, {}×{} target ({} MiB), "
                       "{} light(s), specular {}, fluorescence {}, ssaa {}, readback by {}",
                       bands, layers, passes, MAX_OUTPUTS, targetWidth, targetHeight, targetBytes >> 20,
                       lightCount, hasSpecular ? "on" : "off",
                       !hasFluorescence ? "off" : fluorescenceSpectra ? "on (per-light spectra)" : "on (rank one)", ssaa,
                       mappedReadback ? "mapping a linear image" : "copy");
}

struct SpectralPass::Impl {
    vk::Context& ctx;
    const Scene& scene;
    Grid grid;
    SpectralPassPlan plan;
    PackedScene packed;
    CameraMatrices camera;
    glm::mat4 fullViewProjection{1.0f};
    int rows = 0;

    vk::Buffer vertexBuffer, indexBuffer, lightBuffer, lightSpectraBuffer, materialBuffer, fluorescenceBuffer,
        readbackBuffer;
    VkDeviceSize lightSpectraStride = 0, materialStride = 0, fluorescenceStride = 0;  // dynamic-offset strides
    vk::Image color, depth;
    // Textures (one image per SceneOnGrid texture, then a placeholder) and one descriptor set of
    // set 1 per material.
    std::vector<vk::Image> textures;
    VkSampler textureSampler = VK_NULL_HANDLE;
    VkDescriptorSetLayout textureSetLayout = VK_NULL_HANDLE;
    std::vector<VkDescriptorSet> materialSets;
    std::vector<std::array<int, 3>> materialTextures;  // per material: diffuse, specular, normal texture
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
    PassObjects depthPrePass;

    Impl(vk::Context& c, const Scene& s) : ctx(c), scene(s) {}
    ~Impl() {
        VkDevice d = ctx.device();
        passes.push_back(depthPrePass);
        for (auto& p : passes) {
            if (p.framebuffer) vkDestroyFramebuffer(d, p.framebuffer, nullptr);
            if (p.pipeline) vkDestroyPipeline(d, p.pipeline, nullptr);
            if (p.renderPass) vkDestroyRenderPass(d, p.renderPass, nullptr);
        }
        if (vert) vkDestroyShaderModule(d, vert, nullptr);
        if (descriptorPool) vkDestroyDescriptorPool(d, descriptorPool, nullptr);
        if (pipelineLayout) vkDestroyPipelineLayout(d, pipelineLayout, nullptr);
        if (setLayout) vkDestroyDescriptorSetLayout(d, setLayout, nullptr);
        if (textureSetLayout) vkDestroyDescriptorSetLayout(d, textureSetLayout, nullptr);
        if (textureSampler) vkDestroySampler(d, textureSampler, nullptr);
    }

    VkDeviceSize aligned(VkDeviceSize size) const {
        VkDeviceSize a = std::max<VkDeviceSize>(16, ctx.properties().limits.minUniformBufferOffsetAlignment);
        return (size + a - 1) / a * a;
    }

    // Copies `count` records of `size` bytes into a uniform buffer with records `stride` apart.
    vk::Buffer uniforms(const void* data, size_t size, size_t count, VkDeviceSize stride, const char* name) {
        vk::Buffer b(ctx, std::max<VkDeviceSize>(stride * std::max<size_t>(count, 1), 16),
                     VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, name);
        for (size_t i = 0; i < count; ++i) b.upload(static_cast<const char*>(data) + i * size, size, i * stride);
        return b;
    }

    void createBuffers() {
        if (!packed.vertices.empty()) {
            vertexBuffer = vk::Buffer(ctx, packed.vertices.size() * 4, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, "vertices");
            vertexBuffer.upload(packed.vertices.data(), packed.vertices.size() * 4);
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
    }

    // Each texture as an RGBA32F 2D-array image, 4 channels per layer (zero-padded), copied from a
    // staging buffer; the last image is a 1×1 placeholder for untextured slots.
    void createTextures(const SceneOnGrid& g) {
        std::vector<const TextureOnGrid*> list;
        for (const auto& t : g.textures) list.push_back(&t);
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
                VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
                b.srcAccessMask = 0;
                b.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
                b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
                b.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
                b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
                b.image = image.handle();
                b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, layers};
                vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                                     nullptr, 0, nullptr, 1, &b);
                VkBufferImageCopy region{};
                region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, layers};
                region.imageExtent = {d.width, d.height, 1};
                vkCmdCopyBufferToImage(cmd, staging.handle(), image.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                                       &region);
                b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
                b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
                b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
                b.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
                vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, 0, 0,
                                     nullptr, 0, nullptr, 1, &b);
            });
            textures.push_back(std::move(image));
        }
    }

    void createTargets(Readback mode, bool sampled) {
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
        constexpr int kBindings = 4;
        VkDescriptorSetLayoutBinding bindings[kBindings] = {
            {BINDING_LIGHTS, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
            {BINDING_LIGHT_SPECTRA, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
            {BINDING_MATERIAL, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
            {BINDING_FLUORESCENCE, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        };
        VkDescriptorSetLayoutCreateInfo sl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        sl.bindingCount = kBindings;
        sl.pBindings = bindings;
        VK_CHECK(vkCreateDescriptorSetLayout(d, &sl, nullptr, &setLayout));
        VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                                  sizeof(gpu::SpectralPushConstants)};
        VkDescriptorSetLayoutBinding textureBindings[TEXTURE_BINDINGS];
        for (uint32_t i = 0; i < TEXTURE_BINDINGS; ++i)
            textureBindings[i] = {i, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr};
        VkDescriptorSetLayoutCreateInfo tl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        tl.bindingCount = TEXTURE_BINDINGS;
        tl.pBindings = textureBindings;
        VK_CHECK(vkCreateDescriptorSetLayout(d, &tl, nullptr, &textureSetLayout));
        VkDescriptorSetLayout layouts[2] = {setLayout, textureSetLayout};
        VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        pl.setLayoutCount = 2;
        pl.pSetLayouts = layouts;
        pl.pushConstantRangeCount = 1;
        pl.pPushConstantRanges = &range;
        VK_CHECK(vkCreatePipelineLayout(d, &pl, nullptr, &pipelineLayout));

        const uint32_t materialCount = uint32_t(std::max<size_t>(1, scene.materials.size()));
        VkDescriptorPoolSize sizes[3] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1},
                                         {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 3},
                                         {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, TEXTURE_BINDINGS * materialCount}};
        VkDescriptorPoolCreateInfo pci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        pci.maxSets = 1 + materialCount;
        pci.poolSizeCount = 3;
        pci.pPoolSizes = sizes;
        VK_CHECK(vkCreateDescriptorPool(d, &pci, nullptr, &descriptorPool));
        VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        ai.descriptorPool = descriptorPool;
        ai.descriptorSetCount = 1;
        ai.pSetLayouts = &setLayout;
        VK_CHECK(vkAllocateDescriptorSets(d, &ai, &descriptorSet));
        VkDescriptorBufferInfo infos[kBindings] = {
            {lightBuffer.handle(), 0, sizeof(gpu::GpuLightBlock)},
            {lightSpectraBuffer.handle(), 0, sizeof(gpu::GpuLightSpectraBlock)},
            {materialBuffer.handle(), 0, sizeof(gpu::GpuMaterialBlock)},
            {fluorescenceBuffer.handle(), 0, sizeof(gpu::GpuFluorescenceBlock)}};
        VkWriteDescriptorSet writes[kBindings];
        for (int i = 0; i < kBindings; ++i) {
            writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
            writes[i].dstSet = descriptorSet;
            writes[i].dstBinding = bindings[i].binding;
            writes[i].descriptorCount = 1;
            writes[i].descriptorType = bindings[i].descriptorType;
            writes[i].pBufferInfo = &infos[i];
        }
        vkUpdateDescriptorSets(d, kBindings, writes, 0, nullptr);

        // Set 1 per material: its textures, or the placeholder (texelFetch ignores the sampler's
        // filter; it must still be a valid sampler).
        VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
        sci.magFilter = sci.minFilter = VK_FILTER_NEAREST;
        sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
        sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
        VK_CHECK(vkCreateSampler(d, &sci, nullptr, &textureSampler));
        std::vector<VkDescriptorSetLayout> setLayouts(materialCount, textureSetLayout);
        materialSets.resize(materialCount);
        VkDescriptorSetAllocateInfo mai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        mai.descriptorPool = descriptorPool;
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
                images[i] = {textureSampler, image.layerView(~0u), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
                tw[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
                tw[i].dstSet = materialSets[m];
                tw[i].dstBinding = i;
                tw[i].descriptorCount = 1;
                tw[i].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
                tw[i].pImageInfo = &images[i];
            }
            vkUpdateDescriptorSets(d, TEXTURE_BINDINGS, tw, 0, nullptr);
        }

        vert = vk::createShaderModule(d, kSpirv_spectral_vert, sizeof(kSpirv_spectral_vert));
    }

    // attachments == 0: the depth pre-pass (clears and writes depth). Otherwise a colour pass that
    // loads the pre-pass's depth and shades only the visible surface (depth test EQUAL), so every
    // pixel is shaded once per pass whatever the overdraw.
    VkRenderPass makeRenderPass(uint32_t attachments) {
        std::vector<VkAttachmentDescription> descs;
        std::vector<VkAttachmentReference> refs;
        VkImageLayout finalLayout =
            plan.mappedReadback ? VK_IMAGE_LAYOUT_GENERAL : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        for (uint32_t i = 0; i < attachments; ++i) {
            VkAttachmentDescription a{};
            a.format = VK_FORMAT_R32G32B32A32_SFLOAT;
            a.samples = VK_SAMPLE_COUNT_1_BIT;
            // Cleared once per frame by vkCmdClearColorImage in record(), not by the render pass:
            // lavapipe (Mesa 22.3) leaks about a target's size of memory per render-pass clear of
            // array-layer views (measured: +20 MB per frame at 256² × 89 bands).
            a.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
            a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
            a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
            a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
            a.initialLayout = VK_IMAGE_LAYOUT_GENERAL;
            a.finalLayout = finalLayout;
            descs.push_back(a);
            refs.push_back({i, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL});
        }
        VkAttachmentDescription da{};
        da.format = VK_FORMAT_D32_SFLOAT;
        da.samples = VK_SAMPLE_COUNT_1_BIT;
        bool prePass = attachments == 0;
        da.loadOp = prePass ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
        da.storeOp = VK_ATTACHMENT_STORE_OP_STORE;  // every later pass loads it
        da.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
        da.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        da.initialLayout = prePass ? VK_IMAGE_LAYOUT_UNDEFINED : VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        da.finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        descs.push_back(da);
        VkAttachmentReference depthRef{attachments, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};

        VkSubpassDescription sub{};
        sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
        sub.colorAttachmentCount = attachments;
        sub.pColorAttachments = refs.data();
        sub.pDepthStencilAttachment = &depthRef;
        // The depth image is shared by every pass: wait for the pre-pass's depth writes.
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

    // attachments == 0: the depth pre-pass pipeline (vertex stage only).
    VkPipeline makePipeline(VkRenderPass renderPass, uint32_t attachments) {
        struct Spec {
            int32_t ambient, directional, point;
            VkBool32 hasSpecular, hasFluorescence, hasTextures, hasNormalMaps, fluorescenceSpectra;
        } spec{packed.ambient, packed.directional, packed.point, plan.hasSpecular, plan.hasFluorescence,
               scene.hasTextures(), scene.hasNormalMaps(), plan.fluorescenceSpectra};
        VkSpecializationMapEntry entries[8] = {
            {SPEC_AMBIENT_COUNT, offsetof(Spec, ambient), 4},
            {SPEC_DIRECTIONAL_COUNT, offsetof(Spec, directional), 4},
            {SPEC_POINT_COUNT, offsetof(Spec, point), 4},
            {SPEC_HAS_SPECULAR, offsetof(Spec, hasSpecular), 4},
            {SPEC_HAS_FLUORESCENCE, offsetof(Spec, hasFluorescence), 4},
            {SPEC_HAS_TEXTURES, offsetof(Spec, hasTextures), 4},
            {SPEC_HAS_NORMAL_MAPS, offsetof(Spec, hasNormalMaps), 4},
            {SPEC_FLUORESCENCE_SPECTRA, offsetof(Spec, fluorescenceSpectra), 4},
        };
        VkSpecializationInfo si{8, entries, sizeof(Spec), &spec};
        bool prePass = attachments == 0;
        VkShaderModule frag = VK_NULL_HANDLE;
        if (!prePass) {
            const SpirvCode& fragCode = kSpectralFrag[attachments - 1];
            frag = vk::createShaderModule(ctx.device(), fragCode.code, fragCode.bytes);
        }
        vk::GraphicsPipelineDesc d;
        d.renderPass = renderPass;
        d.layout = pipelineLayout;
        d.vertex = vert;
        d.fragment = frag;
        d.fragmentSpecialization = &si;
        d.bindings = {{0, VERTEX_FLOATS * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX}};
        d.attributes = {{VERTEX_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                        {VERTEX_NORMAL, 0, VK_FORMAT_R32G32B32_SFLOAT, 3 * sizeof(float)},
                        {VERTEX_UV, 0, VK_FORMAT_R32G32_SFLOAT, 6 * sizeof(float)},
                        {VERTEX_TANGENT, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 8 * sizeof(float)}};
        d.width = plan.targetWidth;
        d.height = plan.targetHeight;
        d.colorAttachments = attachments;
        d.depthTest = true;
        d.depthWrite = prePass;
        // Same vertex shader (gl_Position is invariant) → the same depth in every pass.
        d.depthCompare = prePass ? VK_COMPARE_OP_LESS : VK_COMPARE_OP_EQUAL;
        VkPipeline p = VK_NULL_HANDLE;
        try {
            p = vk::createGraphicsPipeline(ctx.device(), d);
        } catch (...) {
            if (frag) vkDestroyShaderModule(ctx.device(), frag, nullptr);
            throw;
        }
        if (frag) vkDestroyShaderModule(ctx.device(), frag, nullptr);  // the pipeline keeps what it needs
        return p;
    }

    void createPasses() {
        {
            PassObjects pre;
            pre.renderPass = makeRenderPass(0);
            pre.pipeline = makePipeline(pre.renderPass, 0);
            VkImageView view = depth.layerView(0);
            VkFramebufferCreateInfo fb{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
            fb.renderPass = pre.renderPass;
            fb.attachmentCount = 1;
            fb.pAttachments = &view;
            fb.width = plan.targetWidth;
            fb.height = plan.targetHeight;
            fb.layers = 1;
            VK_CHECK(vkCreateFramebuffer(ctx.device(), &fb, nullptr, &pre.framebuffer));
            depthPrePass = pre;
        }
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
        VkDeviceSize zero = 0;
        VkBuffer vb = vertexBuffer.handle();
        {
            // Zero every layer (background radiance is 0), in GENERAL, then let the colour passes load it.
            VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, uint32_t(plan.layers)};
            VkImageMemoryBarrier toClear{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
            toClear.srcAccessMask = VK_ACCESS_HOST_READ_BIT | VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
            toClear.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            toClear.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
            toClear.newLayout = VK_IMAGE_LAYOUT_GENERAL;
            toClear.srcQueueFamilyIndex = toClear.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            toClear.image = color.handle();
            toClear.subresourceRange = all;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr,
                                 0, nullptr, 1, &toClear);
            VkClearColorValue black{{0, 0, 0, 0}};
            vkCmdClearColorImage(cmd, color.handle(), VK_IMAGE_LAYOUT_GENERAL, &black, 1, &all);
            VkImageMemoryBarrier toDraw = toClear;
            toDraw.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            toDraw.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
            toDraw.oldLayout = VK_IMAGE_LAYOUT_GENERAL;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0, 0,
                                 nullptr, 0, nullptr, 1, &toDraw);
        }
        {
            VkClearValue clear{};
            clear.depthStencil = {1.0f, 0};
            VkRenderPassBeginInfo rb{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
            rb.renderPass = depthPrePass.renderPass;
            rb.framebuffer = depthPrePass.framebuffer;
            rb.renderArea = {{0, 0}, {plan.targetWidth, plan.targetHeight}};
            rb.clearValueCount = 1;
            rb.pClearValues = &clear;
            vkCmdBeginRenderPass(cmd, &rb, VK_SUBPASS_CONTENTS_INLINE);
            if (!packed.draws.empty()) {
                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, depthPrePass.pipeline);
                vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &zero);
                vkCmdBindIndexBuffer(cmd, indexBuffer.handle(), 0, VK_INDEX_TYPE_UINT32);
                vkCmdPushConstants(cmd, pipelineLayout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                                   sizeof(pc), &pc);
                for (const Draw& d : packed.draws) vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
            }
            vkCmdEndRenderPass(cmd);
        }
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
                vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &zero);
                vkCmdBindIndexBuffer(cmd, indexBuffer.handle(), 0, VK_INDEX_TYPE_UINT32);
                vkCmdPushConstants(cmd, pipelineLayout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                                   sizeof(pc), &pc);
                size_t materials = packed.materials.size() / passes.size();
                for (const Draw& d : packed.draws) {
                    // This pass's bands of the light spectra, of the draw's material and of its
                    // fluorescence.
                    uint32_t offsets[3] = {
                        uint32_t(p * lightSpectraStride), uint32_t((p * materials + d.material) * materialStride),
                        packed.fluorescenceSpectra
                            ? uint32_t((p * packed.fluorescenceRecords + packed.fluorescenceRecord[d.material]) *
                                       fluorescenceStride)
                            : 0u};
                    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelineLayout, 0, 1,
                                            &descriptorSet, 3, offsets);
                    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelineLayout, 1, 1,
                                            &materialSets[d.material], 0, nullptr);
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
        const int s = plan.ssaa, bands = plan.bands, W = cube.width, H = cube.height, layers = plan.layers;
        auto copyRows = [&](int y0, int y1) {
            // One layer row at a time: 4 bands of every pixel, strided into the cube.
            for (int y = y0; y < y1; ++y)
                for (int l = 0; l < layers; ++l) {
                    const float* row = a.row(uint32_t(l), uint32_t(y));
                    int n = std::min(4, bands - 4 * l);
                    float* out = cube.pixel(0, y) + 4 * l;
                    if (n == 4)
                        for (int x = 0; x < W; ++x, out += bands) std::memcpy(out, row + 4 * x, 16);
                    else
                        for (int x = 0; x < W; ++x, out += bands) std::memcpy(out, row + 4 * x, 4 * n);
                }
        };
        auto filterRows = [&](int y0, int y1) {
            const float norm = 1.0f / float(s * s);
            std::vector<float> acc(size_t(W) * 4);
            for (int y = y0; y < y1; ++y)
                for (int l = 0; l < layers; ++l) {
                    std::fill(acc.begin(), acc.end(), 0.0f);
                    for (int sy = 0; sy < s; ++sy) {
                        const float* row = a.row(uint32_t(l), uint32_t(y * s + sy));
                        for (int x = 0; x < W; ++x)
                            for (int sx = 0; sx < s; ++sx)
                                for (int c = 0; c < 4; ++c) acc[x * 4 + c] += row[(x * s + sx) * 4 + c];
                    }
                    int n = std::min(4, bands - 4 * l);
                    for (int x = 0; x < W; ++x)
                        for (int c = 0; c < n; ++c) cube.at(x, y, 4 * l + c) = acc[x * 4 + c] * norm;
                }
        };
        int threads = std::max(1, std::min<int>(int(std::thread::hardware_concurrency()), H));
        std::vector<std::thread> pool;
        for (int t = 0; t < threads; ++t) {
            int y0 = H * t / threads, y1 = H * (t + 1) / threads;
            if (s == 1)
                pool.emplace_back(copyRows, y0, y1);
            else
                pool.emplace_back(filterRows, y0, y1);
        }
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
    if (options.stripRows < 0) failRuntime("strip rows must be ≥ 0, got {}", options.stripRows);
    int rows = options.stripRows > 0 ? std::min(options.stripRows, scene.camera.height) : scene.camera.height;
    p.targetHeight = uint32_t(rows * options.ssaa);
    p.targetBytes = size_t(p.targetWidth) * p.targetHeight * p.layers * 16;
    uint32_t maxDim = ctx.properties().limits.maxFramebufferWidth;
    if (p.targetWidth > maxDim || p.targetHeight > ctx.properties().limits.maxFramebufferHeight)
        failInput(Where{"", "camera"}, "render target {}×{} exceeds the device limit {}×{}", p.targetWidth,
                  p.targetHeight, maxDim, ctx.properties().limits.maxFramebufferHeight);

    Impl& m = *impl_;
    m.plan = p;
    m.grid = spectra.grid;
    if (scene.lights.size() > MAX_LIGHTS)
        failInput(Where{scene.file.string(), "lights"}, "{} lights; the GPU path supports at most {}",
                  scene.lights.size(), MAX_LIGHTS);
    m.packed = pack(scene, spectra, p.passes);
    m.plan.fluorescenceSpectra = m.packed.fluorescenceSpectra;
    m.camera = cameraMatrices(scene.camera, scene);
    m.fullViewProjection = m.camera.viewProjection;
    m.rows = rows;
    if (options.stripRows > 0) setStrip(0);
    m.createBuffers();
    for (const MaterialOnGrid& mat : spectra.materials)
        m.materialTextures.push_back({mat.diffuseTexture, mat.specularTexture, mat.normalTexture});
    m.createTextures(spectra);
    m.createTargets(options.readback, options.sampled);
    m.createLayouts();
    m.createPasses();
    plan_ = m.plan;
    timings_.upload_ms = msSince(t0);
}

SpectralPass::~SpectralPass() = default;

SpectralCube SpectralPass::render() {
    SpectralCube cube;
    render(cube);
    return cube;
}

void SpectralPass::render(SpectralCube& cube) {
    draw();
    readback(cube);
}

int SpectralPass::rows() const { return impl_->rows; }

void SpectralPass::setStrip(int firstRow) {
    // Rows [r0, r0 + R) of an H-row image span clip-space y in [−1 + 2·r0/H, −1 + 2·(r0 + R)/H]
    // (y down); scale and shift that range onto [−1, 1] so the strip fills the target.
    Impl& m = *impl_;
    double H = m.scene.camera.height, R = m.rows, r0 = firstRow;
    glm::mat4 strip(1.0f);
    strip[1][1] = float(H / R);
    strip[3][1] = float((H - 2.0 * r0) / R - 1.0);
    m.camera.viewProjection = strip * m.fullViewProjection;
}

void SpectralPass::setCamera(const Camera& camera) {
    Impl& m = *impl_;
    if (camera.width != m.scene.camera.width || camera.height != m.scene.camera.height)
        failRuntime("SpectralPass::setCamera: the image is {}×{}, the camera asks for {}×{}", m.scene.camera.width,
                    m.scene.camera.height, camera.width, camera.height);
    m.camera = cameraMatrices(camera, m.scene);
    m.fullViewProjection = m.camera.viewProjection;
}

void SpectralPass::draw() {
    Impl& m = *impl_;
    auto t0 = Clock::now();
    m.ctx.submitAndWait([&](VkCommandBuffer cmd) { m.record(cmd); });
    timings_.shading_ms = msSince(t0);
}

VkImage SpectralPass::targetImage() const { return impl_->color.handle(); }
VkImageView SpectralPass::targetArrayView() { return impl_->color.layerView(~0u); }
VkImageLayout SpectralPass::targetLayout() const {
    return plan_.mappedReadback ? VK_IMAGE_LAYOUT_GENERAL : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
}

void SpectralPass::readback(SpectralCube& cube) {
    Impl& m = *impl_;
    auto t1 = Clock::now();
    if (cube.width != m.scene.camera.width || cube.height != m.rows || !(cube.grid == m.grid) ||
        cube.data.size() != size_t(cube.width) * cube.height * cube.bands())
        cube = SpectralCube(m.scene.camera.width, m.rows, m.grid);
    m.readInto(cube);
    timings_.readback_ms = msSince(t1);
}

}  // namespace metamer
