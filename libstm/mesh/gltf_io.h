#pragma once
/// glTF 2.0 (.glb binary, .gltf JSON with embedded or external buffers) through tinygltf (Debian's
/// libtinygltf-dev): triangle primitives read into a mesh soup, meshes written with their uv and
/// texture embedded, so one file carries a textured model to web viewers and game engines.
#include "libstm/core/image.h"
#include "libstm/mesh/mesh.h"

#include <string>

namespace sdm {

struct GltfScene {
  MeshSoup soup;   ///< points welded by position (glTF splits vertices at uv seams), uv per corner
  Image texture;   ///< the base colour texture of the first textured primitive (RGBA), or empty
};

/// Reads every triangle primitive (mode 4, indexed or not) of the default scene's nodes (or of every
/// mesh when the file has no scene), placed by the nodes' transforms. Vertices at the same position
/// become one point (so a closed model split at its seams reads back closed); TEXCOORD_0 becomes the
/// corners' uv when every primitive has it, with v flipped (glTF's v runs down the image, sdm's up).
/// \throw InputError naming the file for a parse error, an accessor outside its buffer, indices
/// outside their primitive, non-float positions, or other primitive modes than triangles only.
GltfScene read_gltf(const std::string& path);

/// Writes `mesh` as .glb or .gltf (by extension; buffers and the image embedded either way):
/// positions and normals, uv (v flipped) when the mesh has them, and `texture_png` (a PNG file's
/// path; its bytes embedded unchanged) as the base colour texture of an unlit-looking PBR material
/// (metallic 0, roughness 1). Vertices are split where their corners' uv differ. Atomic, checked.
void write_gltf(const Mesh& mesh, const std::string& path, const std::string& texture_png = "");

}  // namespace sdm
