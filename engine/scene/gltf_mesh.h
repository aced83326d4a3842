// glTF 2.0 meshes (.gltf with embedded or external buffers, .glb) read into one triangle mesh.
#pragma once

#include "core/error.h"
#include "scene/readable_paths.h"
#include "scene/scene.h"

#include <filesystem>

namespace metamer {

// Every primitive of every mesh reachable from the file's default scene (or scene 0; or, with no
// scenes, every root node), with node transforms applied, in the file's own coordinates (glTF
// metres, +y up). Only TRIANGLES primitives are accepted. NORMAL is used when present, else
// area-weighted smooth normals are computed per primitive; missing indices are generated.
// Winding is kept as in the file (it defines the front face), except that a mirroring node
// transform reverses it, as glTF specifies. Materials, textures, skins and animations are ignored.
// Errors are input errors at `where` (the scene's object key) that name `path`.
// Files the glTF references (buffers, images) are read only where `readable` allows (null: any);
// tinygltf would otherwise follow "../" in URIs and fall back to the current directory.
Mesh loadGltfMesh(const std::filesystem::path& path, const Where& where, const ReadablePaths* readable = nullptr);

}  // namespace metamer
