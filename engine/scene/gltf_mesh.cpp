#include "scene/gltf_mesh.h"

#include "scene/shapes.h"

#include <tiny_gltf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

namespace fs = std::filesystem;

namespace metamer {

namespace {

struct Reader {
    const tinygltf::Model& model;
    const Where& where;
    std::string path;

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

    View view(int index, int type, const std::string& what) const {
        if (index < 0 || static_cast<size_t>(index) >= model.accessors.size())
            fail("{}: accessor {} does not exist", what, index);
        const tinygltf::Accessor& a = model.accessors[index];
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
        size_t viewEnd = std::min(bv.byteOffset + bv.byteLength, buf.data.size());
        size_t first = bv.byteOffset + a.byteOffset;
        size_t end = first + (a.count - 1) * v.stride + size_t(componentSize) * components;
        if (end > viewEnd) fail("{}: accessor {} reads past the end of its buffer", what, index);
        v.data = buf.data.data() + first;
        return v;
    }

    std::vector<glm::dvec3> vec3s(int index, const std::string& what) const {
        View v = view(index, TINYGLTF_TYPE_VEC3, what);
        if (v.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
            fail("{}: expected 32-bit float components (quantized meshes are not supported)", what);
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

    std::vector<uint32_t> indices(int index, const std::string& what) const {
        View v = view(index, TINYGLTF_TYPE_SCALAR, what);
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
        return m;
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

    void visit(int nodeIndex, const glm::dmat4& parent, int depth, Mesh& out) const {
        if (nodeIndex < 0 || static_cast<size_t>(nodeIndex) >= model.nodes.size())
            fail("node {} does not exist", nodeIndex);
        // glTF node graphs are trees; a deeper walk than there are nodes means a cycle.
        if (depth > static_cast<int>(model.nodes.size())) fail("the node hierarchy has a cycle");
        const tinygltf::Node& node = model.nodes[nodeIndex];
        glm::dmat4 world = parent * localMatrix(node);
        if (node.mesh >= 0) {
            if (static_cast<size_t>(node.mesh) >= model.meshes.size())
                fail("node {}: mesh {} does not exist", nodeIndex, node.mesh);
            double det = glm::determinant(glm::dmat3(world));
            if (!std::isfinite(det) || std::fabs(det) < 1e-300)
                fail("node {}: its transform is singular", nodeIndex);
            for (size_t p = 0; p < model.meshes[node.mesh].primitives.size(); ++p) {
                Mesh m = primitive(node.mesh, static_cast<int>(p));
                transformMesh(m, world);
                uint32_t base = static_cast<uint32_t>(out.positions.size());
                out.positions.insert(out.positions.end(), m.positions.begin(), m.positions.end());
                out.normals.insert(out.normals.end(), m.normals.begin(), m.normals.end());
                for (uint32_t i : m.indices) out.indices.push_back(base + i);
            }
        }
        for (int child : node.children) visit(child, world, depth + 1, out);
    }
};

// We only need geometry: skip decoding (and failing on) texture images.
bool ignoreImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                 const unsigned char*, int, void*) {
    return true;
}

}  // namespace

Mesh loadGltfMesh(const fs::path& path, const Where& where) {
    std::string shown = path.string();
    std::error_code ec;
    if (!fs::exists(path, ec)) failInput(where, "mesh file '{}' not found", shown);
    if (!fs::is_regular_file(path, ec)) failInput(where, "mesh file '{}' is not a file", shown);
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext != ".gltf" && ext != ".glb")
        failInput(where, "mesh file '{}' is not glTF: expected a .gltf or .glb file", shown);

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(ignoreImage, nullptr);
    tinygltf::Model model;
    std::string err, warning;
    bool ok = ext == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warning, path.string())
                            : loader.LoadASCIIFromFile(&model, &err, &warning, path.string());
    auto tidy = [](std::string s) {
        while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
        for (char& c : s)
            if (c == '\n') c = ';';
        return s;
    };
    if (!ok) failInput(where, "mesh file '{}' is not valid glTF: {}", shown, tidy(err));
    if (!warning.empty()) warn(where, fmt::format("mesh file '{}': {}", shown, tidy(warning)));
    if (!model.extensionsRequired.empty())
        failInput(where, "mesh file '{}' requires the unsupported extension '{}'", shown,
                  model.extensionsRequired.front());

    Reader reader{model, where, shown};
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
    Mesh out;
    for (int r : roots) reader.visit(r, glm::dmat4(1.0), 0, out);
    if (out.indices.empty()) reader.fail("the default scene contains no triangles");
    return out;
}

}  // namespace metamer
