#include "scene/gltf_mesh.h"
#include "core/file_reads.h"
#include "core/memory_limits.h"

#include "scene/shapes.h"

#include <tiny_gltf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

namespace fs = std::filesystem;

namespace metamer {

namespace {

// glTF's component types (glTF 2.0, "Accessor"), for messages.
const char* componentTypeName(int type) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: return "byte";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "unsigned byte";
        case TINYGLTF_COMPONENT_TYPE_SHORT: return "short";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "unsigned short";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "unsigned int";
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return "float";
        default: return "not a glTF component type";
    }
}

constexpr int kMaxNodeDepth = 1000;  // far beyond any modelled hierarchy

struct Reader {
    const tinygltf::Model& model;
    const Where& where;
    std::string path;
    // The decoded bytes of images given as data: URIs, by image index (tinygltf hands them only to
    // its image callback; buffer-view images are read from the model, bounds-checked).
    const std::map<int, std::vector<unsigned char>>& dataUriImages;
    mutable std::map<std::pair<int, int>, Mesh> decoded;  // (mesh, primitive) → its triangles

    template <typename... Args>
    [[noreturn]] void fail(fmt::format_string<Args...> f, Args&&... args) const {
        failInput(where, "mesh file '{}': {}", path, fmt::format(f, std::forward<Args>(args)...));
    }

    // The bytes of an accessor, bounds-checked against its buffer view and buffer.
    struct View {
        const unsigned char* data = nullptr;
        size_t stride = 0;
        size_t count = 0;
        int componentType = 0;
    };

    // `componentTypes`: the component types this use of the accessor reads, checked before the layout,
    // so that indices of floats (or of a type glTF does not define) are named as such rather than
    // as reading past their buffer.
    View view(int index, int type, const std::string& what, std::initializer_list<int> componentTypes,
              const char* expected) const {
        if (index < 0 || static_cast<size_t>(index) >= model.accessors.size())
            fail("{}: accessor {} does not exist", what, index);
        const tinygltf::Accessor& a = model.accessors[index];
        if (std::find(componentTypes.begin(), componentTypes.end(), a.componentType) == componentTypes.end())
            fail("{}: accessor {} has component type {} ({}); expected {}", what, index, a.componentType,
                 componentTypeName(a.componentType), expected);
        if (a.sparse.isSparse) fail("{}: sparse accessors are not supported", what);
        if (a.bufferView < 0) fail("{}: accessor {} has no buffer view", what, index);
        if (a.type != type) fail("{}: accessor {} has the wrong element type", what, index);
        if (static_cast<size_t>(a.bufferView) >= model.bufferViews.size())
            fail("{}: buffer view {} does not exist", what, a.bufferView);
        const tinygltf::BufferView& bv = model.bufferViews[a.bufferView];
        if (bv.buffer < 0 || static_cast<size_t>(bv.buffer) >= model.buffers.size())
            fail("{}: buffer {} does not exist", what, bv.buffer);
        const tinygltf::Buffer& buf = model.buffers[bv.buffer];
        int stride = a.ByteStride(bv);
        int componentSize = tinygltf::GetComponentSizeInBytes(a.componentType);
        int components = tinygltf::GetNumComponentsInType(a.type);
        if (stride <= 0 || componentSize <= 0 || components <= 0)
            fail("{}: accessor {} has an invalid layout", what, index);
        View v;
        v.stride = static_cast<size_t>(stride);
        v.count = a.count;
        v.componentType = a.componentType;
        if (a.count == 0) return v;
        // Offsets and counts come from the file and can be anything up to 2^64: compare by
        // subtraction so that no sum or product wraps around (a count of 2^62 times a 12-byte
        // stride is 0 modulo 2^64, which a product-based check would accept).
        const size_t bufferSize = buf.data.size();
        if (bv.byteOffset > bufferSize) fail("{}: buffer view {} starts past the end of its buffer", what, a.bufferView);
        const size_t viewEnd = bv.byteOffset + std::min(bv.byteLength, bufferSize - bv.byteOffset);
        const size_t element = size_t(componentSize) * size_t(components);
        if (a.byteOffset > viewEnd - bv.byteOffset || viewEnd - bv.byteOffset - a.byteOffset < element)
            fail("{}: accessor {} reads past the end of its buffer", what, index);
        const size_t first = bv.byteOffset + a.byteOffset;
        if (a.count - 1 > (viewEnd - first - element) / v.stride)
            fail("{}: accessor {} reads past the end of its buffer ({} elements)", what, index, a.count);
        v.data = buf.data.data() + first;
        return v;
    }

    std::vector<glm::dvec3> vec3s(int index, const std::string& what) const {
        View v = view(index, TINYGLTF_TYPE_VEC3, what, {TINYGLTF_COMPONENT_TYPE_FLOAT},
                      "32-bit float components (quantized meshes are not supported)");
        std::vector<glm::dvec3> out(v.count);
        for (size_t i = 0; i < v.count; ++i) {
            float f[3];
            std::memcpy(f, v.data + i * v.stride, sizeof f);
            if (!std::isfinite(f[0]) || !std::isfinite(f[1]) || !std::isfinite(f[2]))
                fail("{}: element {} is not finite", what, i);
            out[i] = glm::dvec3(f[0], f[1], f[2]);
        }
        return out;
    }

    // TEXCOORD_n: float, or unsigned byte/short normalized to [0, 1] (glTF allows all three).
    std::vector<glm::dvec2> vec2s(int index, const std::string& what) const {
        View v = view(index, TINYGLTF_TYPE_VEC2, what,
                      {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                       TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
                      "texture coordinates of float or normalized unsigned byte/short");
        std::vector<glm::dvec2> out(v.count);
        for (size_t i = 0; i < v.count; ++i) {
            const unsigned char* p = v.data + i * v.stride;
            switch (v.componentType) {
                case TINYGLTF_COMPONENT_TYPE_FLOAT: {
                    float f[2];
                    std::memcpy(f, p, sizeof f);
                    if (!std::isfinite(f[0]) || !std::isfinite(f[1])) fail("{}: element {} is not finite", what, i);
                    out[i] = glm::dvec2(f[0], f[1]);
                    break;
                }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: out[i] = glm::dvec2(p[0], p[1]) / 255.0; break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                    uint16_t x[2];
                    std::memcpy(x, p, sizeof x);
                    out[i] = glm::dvec2(x[0], x[1]) / 65535.0;
                    break;
                }
                default: fail("{}: texture coordinates must be float or normalized unsigned byte/short", what);
            }
        }
        return out;
    }

    std::vector<glm::dvec4> vec4s(int index, const std::string& what) const {
        View v = view(index, TINYGLTF_TYPE_VEC4, what, {TINYGLTF_COMPONENT_TYPE_FLOAT}, "32-bit float components");
        std::vector<glm::dvec4> out(v.count);
        for (size_t i = 0; i < v.count; ++i) {
            float f[4];
            std::memcpy(f, v.data + i * v.stride, sizeof f);
            for (float x : f)
                if (!std::isfinite(x)) fail("{}: element {} is not finite", what, i);
            out[i] = glm::dvec4(f[0], f[1], f[2], f[3]);
        }
        return out;
    }

    std::vector<uint32_t> indices(int index, const std::string& what) const {
        View v = view(index, TINYGLTF_TYPE_SCALAR, what,
                      {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                       TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
                      "indices of unsigned byte, short or int");
        std::vector<uint32_t> out(v.count);
        for (size_t i = 0; i < v.count; ++i) {
            const unsigned char* p = v.data + i * v.stride;
            switch (v.componentType) {
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: out[i] = *p; break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                    uint16_t x;
                    std::memcpy(&x, p, 2);
                    out[i] = x;
                    break;
                }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: std::memcpy(&out[i], p, 4); break;
                default: fail("{}: indices must be unsigned byte, short or int", what);
            }
        }
        return out;
    }

    // The triangles of one primitive, in the primitive's own coordinates.
    Mesh primitive(int meshIndex, int primIndex) const {
        const tinygltf::Primitive& prim = model.meshes[meshIndex].primitives[primIndex];
        std::string what = fmt::format("mesh {} primitive {}", meshIndex, primIndex);
        if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES)
            fail("{}: mode {} is not TRIANGLES (4); only triangle lists are supported", what, prim.mode);
        auto pos = prim.attributes.find("POSITION");
        if (pos == prim.attributes.end()) fail("{}: no POSITION attribute", what);
        Mesh m;
        m.positions = vec3s(pos->second, what + " POSITION");
        if (prim.indices >= 0) {
            m.indices = indices(prim.indices, what + " indices");
        } else {
            m.indices.resize(m.positions.size());
            for (size_t i = 0; i < m.indices.size(); ++i) m.indices[i] = static_cast<uint32_t>(i);
        }
        if (m.indices.size() % 3 != 0)
            fail("{}: {} indices is not a whole number of triangles", what, m.indices.size());
        for (uint32_t i : m.indices)
            if (i >= m.positions.size())
                fail("{}: index {} is out of range ({} vertices)", what, i, m.positions.size());
        if (auto nrm = prim.attributes.find("NORMAL"); nrm != prim.attributes.end()) {
            m.normals = vec3s(nrm->second, what + " NORMAL");
            if (m.normals.size() != m.positions.size())
                fail("{}: {} normals for {} positions", what, m.normals.size(), m.positions.size());
            for (size_t i = 0; i < m.normals.size(); ++i) {
                double len = glm::length(m.normals[i]);
                if (!(len > 0.0)) fail("{} NORMAL: element {} has zero length", what, i);
                m.normals[i] /= len;
            }
        } else {
            m.normals = smoothNormals(m.positions, m.indices);
        }
        if (auto uv = prim.attributes.find("TEXCOORD_0"); uv != prim.attributes.end()) {
            m.uvs = vec2s(uv->second, what + " TEXCOORD_0");
            if (m.uvs.size() != m.positions.size())
                fail("{}: {} texture coordinates for {} positions", what, m.uvs.size(), m.positions.size());
            if (auto tan = prim.attributes.find("TANGENT"); tan != prim.attributes.end()) {
                m.tangents = vec4s(tan->second, what + " TANGENT");
                if (m.tangents.size() != m.positions.size())
                    fail("{}: {} tangents for {} positions", what, m.tangents.size(), m.positions.size());
                for (auto& t : m.tangents) {
                    // Unit xyz and w = ±1 by the specification; a zero one means "none here".
                    double len = glm::length(glm::dvec3(t));
                    t = len > 0.0 ? glm::dvec4(glm::dvec3(t) / len, t.w < 0.0 ? -1.0 : 1.0) : glm::dvec4(0.0);
                }
            } else {
                m.tangents = tangentsFromUvs(m.positions, m.normals, m.uvs, m.indices);
            }
        }
        m.material = prim.material >= 0 ? uint32_t(prim.material) : kNoGltfMaterial;
        return m;
    }

    // A texture reference of a material: the image's file, or its bytes when it is embedded.
    std::optional<GltfImage> image(const tinygltf::TextureInfo& info, const std::string& what, const std::string& dir) const {
        if (info.index < 0) return std::nullopt;
        if (size_t(info.index) >= model.textures.size()) fail("{}: texture {} does not exist", what, info.index);
        int source = model.textures[info.index].source;
        if (source < 0 || size_t(source) >= model.images.size()) fail("{}: texture {} has no image", what, info.index);
        if (info.texCoord != 0)
            warn(where, fmt::format("mesh file '{}': {} uses TEXCOORD_{}; only TEXCOORD_0 is read, so it is used "
                                    "instead", path, what, info.texCoord));
        if (info.extensions.count("KHR_texture_transform"))
            warn(where, fmt::format("mesh file '{}': {} has a KHR_texture_transform, which is not applied: the "
                                    "texture is mapped by TEXCOORD_0 as it is", path, what));
        if (int sampler = model.textures[info.index].sampler; sampler >= 0 && size_t(sampler) < model.samplers.size()) {
            const tinygltf::Sampler& smp = model.samplers[sampler];
            for (int mode : {smp.wrapS, smp.wrapT})
                if (mode != TINYGLTF_TEXTURE_WRAP_REPEAT) {
                    warn(where, fmt::format("mesh file '{}': {} asks for {} wrapping; textures repeat here (the "
                                            "texels at an edge blend with the opposite edge's)",
                                            path, what, mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE ? "clamp-to-edge" : "mirrored"));
                    break;
                }
        }
        const tinygltf::Image& img = model.images[source];
        GltfImage out;
        if (img.bufferView >= 0 || img.uri.empty()) {
            out.name = img.name.empty() ? fmt::format("{} image {}", path, source)
                                        : fmt::format("{} image {} ('{}')", path, source, img.name);
            if (img.bufferView >= 0) {
                if (size_t(img.bufferView) >= model.bufferViews.size())
                    fail("{}: image {}'s buffer view {} does not exist", what, source, img.bufferView);
                const tinygltf::BufferView& bv = model.bufferViews[img.bufferView];
                if (bv.buffer < 0 || size_t(bv.buffer) >= model.buffers.size())
                    fail("{}: image {}'s buffer {} does not exist", what, source, bv.buffer);
                const std::vector<unsigned char>& data = model.buffers[bv.buffer].data;
                if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
                    fail("{}: image {}'s buffer view {} reads past the end of its buffer", what, source, img.bufferView);
                out.embedded.assign(data.begin() + std::ptrdiff_t(bv.byteOffset),
                                    data.begin() + std::ptrdiff_t(bv.byteOffset + bv.byteLength));
            } else if (auto it = dataUriImages.find(source); it != dataUriImages.end()) {
                out.embedded = it->second;
            }
            if (out.embedded.empty()) fail("{}: image {} is embedded but holds no data", what, source);
            return out;
        }
        // URIs are percent-encoded (RFC 3986): "%20" is a space.
        std::string uri;
        for (size_t k = 0; k < img.uri.size(); ++k) {
            if (img.uri[k] == '%' && k + 2 < img.uri.size() && std::isxdigit(static_cast<unsigned char>(img.uri[k + 1])) &&
                std::isxdigit(static_cast<unsigned char>(img.uri[k + 2]))) {
                uri += char(std::stoi(img.uri.substr(k + 1, 2), nullptr, 16));
                k += 2;
            } else {
                uri += img.uri[k];
            }
        }
        out.file = (fs::path(dir) / uri).lexically_normal();
        out.name = out.file.string();
        return out;
    }

    GltfMaterial material(int index, const std::string& dir) const {
        const tinygltf::Material& m = model.materials[index];
        GltfMaterial g;
        g.index = index;
        g.name = m.name.empty() ? fmt::format("material{}", index) : m.name;
        std::string what = fmt::format("material {} ('{}')", index, g.name);
        const auto& pbr = m.pbrMetallicRoughness;
        if (pbr.baseColorFactor.size() == 4)
            g.baseColorFactor = glm::dvec4(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2],
                                           pbr.baseColorFactor[3]);
        for (int c = 0; c < 4; ++c)
            if (!(g.baseColorFactor[c] >= 0.0 && g.baseColorFactor[c] <= 1.0))
                fail("{}: baseColorFactor component {} is {}; expected [0, 1]", what, c, g.baseColorFactor[c]);
        g.metallic = pbr.metallicFactor;
        g.roughness = pbr.roughnessFactor;
        if (!(g.metallic >= 0.0 && g.metallic <= 1.0)) fail("{}: metallicFactor {} is outside [0, 1]", what, g.metallic);
        if (!(g.roughness >= 0.0 && g.roughness <= 1.0)) fail("{}: roughnessFactor {} is outside [0, 1]", what, g.roughness);
        g.baseColorTexture = image(pbr.baseColorTexture, what + " baseColorTexture", dir);
        if (pbr.metallicRoughnessTexture.index >= 0)
            warn(where, fmt::format("mesh file '{}': {} has a metallicRoughnessTexture; its factors are used, the "
                                    "texture is not",
                                    path, what));
        tinygltf::TextureInfo normalInfo;
        normalInfo.index = m.normalTexture.index;
        normalInfo.texCoord = m.normalTexture.texCoord;
        normalInfo.extensions = m.normalTexture.extensions;
        g.normalTexture = image(normalInfo, what + " normalTexture", dir);
        g.normalScale = m.normalTexture.scale;
        if (m.emissiveFactor.size() == 3 && (m.emissiveFactor[0] > 0 || m.emissiveFactor[1] > 0 || m.emissiveFactor[2] > 0))
            warn(where, fmt::format("mesh file '{}': {} is emissive; Metamer has no emitting surfaces, so the "
                                    "emission is left out",
                                    path, what));
        return g;
    }

    static glm::dmat4 localMatrix(const tinygltf::Node& n) {
        if (n.matrix.size() == 16) return glm::make_mat4(n.matrix.data());  // both column-major
        glm::dmat4 m(1.0);
        if (n.translation.size() == 3) m = glm::translate(m, glm::make_vec3(n.translation.data()));
        if (n.rotation.size() == 4) {
            const auto& q = n.rotation;  // glTF stores x, y, z, w
            m = m * glm::mat4_cast(glm::dquat(q[3], q[0], q[1], q[2]));
        }
        if (n.scale.size() == 3) m = glm::scale(m, glm::make_vec3(n.scale.data()));
        return m;
    }

    // What the default scene expands to, counted from the accessors before any vertex is decoded.
    struct Expansion {
        size_t instances = 0, vertices = 0, indices = 0;
        std::vector<bool> reached;  // by node: each node once (glTF nodes have at most one parent)
    };

    // An accessor's count, at most what its buffer view can hold: a count the file cannot back
    // (2⁶²) is left to view() to name, and cannot wrap the sums around.
    size_t storable(int index) const {
        if (index < 0 || static_cast<size_t>(index) >= model.accessors.size()) return 0;
        const tinygltf::Accessor& a = model.accessors[index];
        if (a.bufferView < 0 || static_cast<size_t>(a.bufferView) >= model.bufferViews.size()) return 0;
        const int size = tinygltf::GetComponentSizeInBytes(a.componentType) * tinygltf::GetNumComponentsInType(a.type);
        return size > 0 ? std::min(a.count, model.bufferViews[a.bufferView].byteLength / size_t(size)) : 0;
    }

    void count(int nodeIndex, int depth, Expansion& e) const {
        if (nodeIndex < 0 || static_cast<size_t>(nodeIndex) >= model.nodes.size())
            fail("node {} does not exist", nodeIndex);
        // Each level is a stack frame here: a chain of a million nodes would overflow the stack.
        if (depth > kMaxNodeDepth) fail("the node hierarchy is deeper than {} levels", kMaxNodeDepth);
        // glTF node graphs are a forest: a node reached twice is a cycle, or a child listed twice —
        // which would otherwise multiply the instances below it at every level.
        if (e.reached[nodeIndex])
            fail("the node hierarchy has a cycle or a shared node: node {} is reached twice (glTF nodes have one "
                 "parent)",
                 nodeIndex);
        e.reached[nodeIndex] = true;
        const tinygltf::Node& node = model.nodes[nodeIndex];
        if (node.mesh >= 0 && static_cast<size_t>(node.mesh) < model.meshes.size())
            for (const tinygltf::Primitive& prim : model.meshes[node.mesh].primitives) {
                ++e.instances;
                const auto position = prim.attributes.find("POSITION");
                const size_t v = position == prim.attributes.end() ? 0 : storable(position->second);
                e.vertices += v;
                e.indices += prim.indices >= 0 ? storable(prim.indices) : v;
            }
        for (int child : node.children) count(child, depth + 1, e);
    }

    void visit(int nodeIndex, const glm::dmat4& parent, int depth, std::vector<Mesh>& out) const {
        const tinygltf::Node& node = model.nodes[nodeIndex];  // checked by count()
        glm::dmat4 world = parent * localMatrix(node);
        if (node.mesh >= 0) {
            if (static_cast<size_t>(node.mesh) >= model.meshes.size())
                fail("node {}: mesh {} does not exist", nodeIndex, node.mesh);
            double det = glm::determinant(glm::dmat3(world));
            if (!std::isfinite(det) || std::fabs(det) < 1e-300)
                fail("node {}: its transform is singular", nodeIndex);
            for (size_t p = 0; p < model.meshes[node.mesh].primitives.size(); ++p) {
                // Decoded once per primitive, however many nodes instance it.
                auto [at, fresh] = decoded.try_emplace({node.mesh, int(p)});
                if (fresh) at->second = primitive(node.mesh, static_cast<int>(p));
                Mesh m = at->second;
                transformMesh(m, world);
                out.push_back(std::move(m));
            }
        }
        for (int child : node.children) visit(child, world, depth + 1, out);
    }
};

// File access for tinygltf: the buffers and images a glTF references are read only where the
// scene may read (readable_paths.h). tinygltf joins a URI to the glTF's folder and, failing that,
// to the current directory, and follows "../"; the callbacks see the joined path.
struct FileAccess {
    const ReadablePaths* readable = nullptr;
    std::vector<std::string> refused;  // paths not read because they lie outside
};

bool fileExists(const std::string& path, void*) {
    std::error_code ec;
    return fs::exists(path, ec);
}

// glTF URIs are not shell words: no "~" or "$VAR" expansion.
std::string expandFilePath(const std::string& path, void*) { return path; }

bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    auto* access = static_cast<FileAccess*>(user);
    if (access->readable && !access->readable->allows(path)) {
        access->refused.push_back(path);
        if (err) *err += "outside the folders the scene may read";
        return false;
    }
    // Only regular files: a URI naming a FIFO or /dev/zero would block or never end.
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        if (err) *err += "not a regular file";
        return false;
    }
    noteFileRead(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        if (err) *err += "cannot open the file";
        return false;
    }
    out->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return true;
}

// The deepest nesting of arrays and objects in JSON text (strings skipped). tinygltf converts
// "extras" and "extensions" into its own values recursively, one stack frame per level, so a
// file nesting 100 000 levels deep would crash it: such files are refused before it sees them.
size_t jsonNesting(const unsigned char* text, size_t size) {
    size_t depth = 0, deepest = 0;
    bool inString = false;
    for (size_t i = 0; i < size; ++i) {
        unsigned char c = text[i];
        if (inString) {
            if (c == '\\') ++i;
            else if (c == '"') inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            deepest = std::max(deepest, ++depth);
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

constexpr size_t kMaxGltfJsonDepth = 64;  // glTF itself nests 5 levels; extras rarely a few more

bool writeWholeFile(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "metamer does not write glTF files";
    return false;
}

// Images are not decoded here (the scene loader decodes the ones materials use); the bytes of
// data: URI images are kept, as tinygltf gives them to no one else. Buffer-view images (image
// ->bufferView set) are read from the model later, with bounds checks, and external files by name.
bool keepDataUriImage(tinygltf::Image* image, const int index, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void* user) {
    if (image->bufferView < 0 && image->uri.empty() && size > 0)
        (*static_cast<std::map<int, std::vector<unsigned char>>*>(user))[index].assign(bytes, bytes + size);
    return true;
}

}  // namespace

GltfModel loadGltf(const fs::path& path, const Where& where, const ReadablePaths* readable) {
    std::string shown = path.string();
    requireRegularFile(path, where, "mesh file");
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext != ".gltf" && ext != ".glb")
        failInput(where, "mesh file '{}' is not glTF: expected a .gltf or .glb file", shown);

    tinygltf::TinyGLTF loader;
    std::map<int, std::vector<unsigned char>> dataUriImages;
    loader.SetImageLoader(keepDataUriImage, &dataUriImages);
    FileAccess access{readable, {}};
    loader.SetFsCallbacks(tinygltf::FsCallbacks{fileExists, expandFilePath, readWholeFile, writeWholeFile, &access});

    // Read the file here rather than by name in tinygltf, to look at its JSON before tinygltf does.
    std::vector<unsigned char> bytes;
    std::string readError;
    if (!readWholeFile(&bytes, &readError, path.string(), &access)) {
        if (!access.refused.empty()) failInput(where, "{}", readable->refusal(path, "mesh file", shown));
        failInput(where, "mesh file '{}' cannot be read: {}", shown, readError);
    }
    if (bytes.size() > std::numeric_limits<unsigned int>::max())
        failInput(where, "mesh file '{}' is larger than 4 GiB, more than glTF loading supports", shown);
    const unsigned char* json = bytes.data();
    size_t jsonSize = bytes.size();
    if (ext == ".glb") {
        // GLB: a 12-byte header ("glTF", version, total length), then the JSON chunk's length and
        // type, then the JSON. tinygltf reads the version but accepts any: only 2 is glTF 2.0.
        if (bytes.size() < 20 || std::memcmp(bytes.data(), "glTF", 4) != 0)
            failInput(where, "mesh file '{}' is not a GLB file: it does not start with a 20-byte GLB header "
                      "('glTF', version, length, then the JSON chunk)", shown);
        uint32_t version = 0, totalLength = 0;
        std::memcpy(&version, bytes.data() + 4, 4);
        std::memcpy(&totalLength, bytes.data() + 8, 4);
        if (version != 2)
            failInput(where, "mesh file '{}' is GLB version {}; expected version 2 (glTF 2.0)", shown, version);
        if (totalLength != bytes.size())
            failInput(where, "mesh file '{}': its GLB header says {} bytes but the file has {} (truncated or "
                      "padded?)", shown, totalLength, bytes.size());
    }
    if (ext == ".glb" && bytes.size() >= 20) {
        uint32_t chunkLength = 0;
        std::memcpy(&chunkLength, bytes.data() + 12, 4);
        json = bytes.data() + 20;
        jsonSize = std::min<size_t>(chunkLength, bytes.size() - 20);
    }
    if (jsonNesting(json, jsonSize) > kMaxGltfJsonDepth)
        failInput(where, "mesh file '{}': its JSON nests more than {} levels deep", shown, kMaxGltfJsonDepth);

    tinygltf::Model model;
    std::string err, warning;
    const std::string baseDir = path.parent_path().string();
    const auto length = static_cast<unsigned int>(bytes.size());
    bool ok = ext == ".glb"
                  ? loader.LoadBinaryFromMemory(&model, &err, &warning, bytes.data(), length, baseDir)
                  : loader.LoadASCIIFromString(&model, &err, &warning, reinterpret_cast<const char*>(bytes.data()),
                                               length, baseDir);
    auto tidy = [](std::string s) {
        while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
        for (char& c : s)
            if (c == '\n') c = ';';
        return s;
    };
    if (!ok && !access.refused.empty())
        failInput(where, "mesh file '{}': {}", shown,
                  readable->refusal(access.refused.front(), "referenced file", access.refused.front()));
    if (!ok) failInput(where, "mesh file '{}' is not valid glTF: {}", shown, tidy(err));
    if (!access.refused.empty()) {
        // Loading succeeded, so what was refused was not required: images, which tinygltf tries to
        // read whether or not a material uses them. Say so once, in place of its read-error lines.
        std::string kept;
        std::istringstream lines(warning);
        for (std::string line; std::getline(lines, line);) {
            bool aboutRefused = line.find("Failed to load external 'uri' for image") != std::string::npos;
            for (const auto& r : access.refused) aboutRefused = aboutRefused || line.find(r) != std::string::npos;
            if (!aboutRefused) kept += line + "\n";
        }
        warning = kept;
        warn(where, fmt::format("mesh file '{}': image '{}' not read: it is outside the folders the scene may read "
                                "(a material that uses it is an error; --allow-outside-paths reads it)",
                                shown, access.refused.front()));
    }
    if (!warning.empty()) warn(where, fmt::format("mesh file '{}': {}", shown, tidy(warning)));
    if (!model.extensionsRequired.empty())
        failInput(where, "mesh file '{}' requires the unsupported extension '{}'", shown,
                  model.extensionsRequired.front());

    Reader reader{model, where, shown, dataUriImages};
    std::vector<int> roots;
    if (!model.scenes.empty()) {
        int s = model.defaultScene >= 0 ? model.defaultScene : 0;
        if (static_cast<size_t>(s) >= model.scenes.size()) reader.fail("scene {} does not exist", s);
        roots = model.scenes[s].nodes;
    } else {
        std::vector<bool> isChild(model.nodes.size(), false);
        for (const auto& n : model.nodes)
            for (int c : n.children)
                if (c >= 0 && static_cast<size_t>(c) < isChild.size()) isChild[c] = true;
        for (size_t i = 0; i < model.nodes.size(); ++i)
            if (!isChild[i]) roots.push_back(static_cast<int>(i));
    }
    // Counted before anything is expanded: instancing makes a small file into any number of
    // triangles (300 000 nodes of one mesh), so what the expansion would take is compared with the
    // memory an input may take (a quarter of the machine's, core/memory_limits.h), and refused above.
    Reader::Expansion expansion;
    expansion.reached.assign(model.nodes.size(), false);
    for (int r : roots) reader.count(r, 0, expansion);
    // Per expanded vertex: position, normal, uv, tangent in double (96 bytes), twice (the parts,
    // then the merged mesh); per index 4 bytes, twice.
    const double expandedBytes = 2.0 * (96.0 * double(expansion.vertices) + 4.0 * double(expansion.indices));
    if (expandedBytes > double(decodedImageLimitBytes()))
        reader.fail("its default scene expands to {} triangles in {} mesh instances, about {} once expanded, more "
                    "than the {} an input may take on this machine (a quarter of its memory); instance fewer nodes",
                    expansion.indices / 3, expansion.instances, memorySize(uint64_t(std::min(expandedBytes, 1.8e19))),
                    memorySize(decodedImageLimitBytes()));
    if (expansion.indices / 3 > 10'000'000)
        warn(where, fmt::format("mesh file '{}' expands to {} triangles in {} mesh instances (about {}): loading and "
                                "drawing them takes a while",
                                shown, expansion.indices / 3, expansion.instances, memorySize(uint64_t(expandedBytes))));
    GltfModel out;
    for (int r : roots) reader.visit(r, glm::dmat4(1.0), 0, out.meshes);
    size_t triangles = 0;
    for (const Mesh& m : out.meshes) triangles += m.indices.size();
    if (triangles == 0) reader.fail("the default scene contains no triangles");
    for (size_t i = 0; i < model.materials.size(); ++i) out.materials.push_back(reader.material(int(i), baseDir));
    for (const Mesh& m : out.meshes)
        if (m.material != kNoGltfMaterial && m.material >= out.materials.size())
            reader.fail("a primitive uses material {} but the file has {}", m.material, out.materials.size());
    return out;
}

Mesh mergeMeshes(const std::vector<Mesh>& parts) {
    Mesh out;
    bool uvs = false, tangents = false;
    for (const Mesh& m : parts) {
        uvs = uvs || !m.uvs.empty();
        tangents = tangents || !m.tangents.empty();
    }
    for (const Mesh& m : parts) {
        uint32_t base = static_cast<uint32_t>(out.positions.size());
        out.positions.insert(out.positions.end(), m.positions.begin(), m.positions.end());
        out.normals.insert(out.normals.end(), m.normals.begin(), m.normals.end());
        // A part without texture coordinates (or tangents) gets zeros: no texture detail, no
        // normal mapping there.
        if (uvs) {
            if (m.uvs.empty())
                out.uvs.resize(out.positions.size(), glm::dvec2(0.0));
            else
                out.uvs.insert(out.uvs.end(), m.uvs.begin(), m.uvs.end());
        }
        if (tangents) {
            if (m.tangents.empty())
                out.tangents.resize(out.positions.size(), glm::dvec4(0.0));
            else
                out.tangents.insert(out.tangents.end(), m.tangents.begin(), m.tangents.end());
        }
        for (uint32_t i : m.indices) out.indices.push_back(base + i);
    }
    return out;
}

Mesh loadGltfMesh(const fs::path& path, const Where& where, const ReadablePaths* readable) {
    return mergeMeshes(loadGltf(path, where, readable).meshes);
}

}  // namespace metamer
