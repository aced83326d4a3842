// glTF 2.0 meshes (.gltf with embedded or external buffers, .glb) read into one triangle mesh.
#pragma once

#include "core/error.h"
#include "scene/readable_paths.h"
#include "scene/scene.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace metamer {

// Every primitive of every mesh reachable from the file's default scene (or scene 0; or, with no
// scenes, every root node), with node transforms applied, in the file's own coordinates (glTF
// metres, +y up). Only TRIANGLES primitives are accepted. NORMAL is used when present, else
// area-weighted smooth normals are computed per primitive; missing indices are generated.
// Winding is kept as in the file (it defines the front face), except that a mirroring node
// transform reverses it, as glTF specifies. Materials, skins and animations are ignored.
// Errors are input errors at `where` (the scene's object key) that name `path`.
// Files the glTF references (buffers, images) are read only where `readable` allows (null: any);
// tinygltf would otherwise follow "../" in URIs and fall back to the current directory.
// An image a glTF material uses: a file of its own (the scene loader reads it, under the scene's
// path rules), or one embedded in the glTF file — in a buffer view (as GLB files hold them) or a
// data: URI — whose encoded bytes (PNG or JPEG) are kept here.
struct GltfImage {
    std::filesystem::path file;            // empty for an embedded image
    std::vector<unsigned char> embedded;   // an embedded image's bytes
    std::string name;                      // for messages: the file, or "FILE image 0 ('name')"
    bool isEmbedded() const { return file.empty(); }
};

// A glTF metallic–roughness material, as the file gives it (scene/gltf_material.h turns it into
// a spectral Material).
struct GltfMaterial {
    int index = 0;
    std::string name;                        // the file's name, or "material<index>"
    glm::dvec4 baseColorFactor{1.0};         // linear RGBA
    std::optional<GltfImage> baseColorTexture;  // sRGB-encoded image
    double metallic = 1.0, roughness = 1.0;  // glTF's defaults
    std::optional<GltfImage> normalTexture;
    double normalScale = 1.0;
};

// Primitives use this as their material when the file gives none.
constexpr uint32_t kNoGltfMaterial = 0xffffffffu;

struct GltfModel {
    std::vector<Mesh> meshes;  // one per primitive instance; Mesh::material = the glTF material index
    std::vector<GltfMaterial> materials;
};

// Every primitive as its own mesh, with its glTF material, texture coordinates (TEXCOORD_0) and
// tangents (TANGENT, else from the UVs: shapes.h, tangentsFromUvs). Images in files of their own
// are named, not read; embedded ones are returned as their encoded bytes.
GltfModel loadGltf(const std::filesystem::path& path, const Where& where, const ReadablePaths* readable = nullptr);

// Meshes joined into one (parts without UVs or tangents get zeros).
Mesh mergeMeshes(const std::vector<Mesh>& parts);

Mesh loadGltfMesh(const std::filesystem::path& path, const Where& where, const ReadablePaths* readable = nullptr);

}  // namespace metamer
