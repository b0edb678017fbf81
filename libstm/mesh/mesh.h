#pragma once
/// The one mesh type of the project: an OpenMesh triangle mesh with double-precision points,
/// optional per-halfedge texture coordinates, and the texture image its material names.
#include "libstm/core/image.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <Eigen/Dense>
#include <array>
#include <string>
#include <vector>

namespace sdm {

struct MeshTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  using TexCoord2D = OpenMesh::Vec2d;
  VertexAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::PrevHalfedge | OpenMesh::Attributes::Status);
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

/// A mesh as it came from a file: the triangle list before any topology is built, so that
/// broken input (non-manifold, duplicated faces) can be counted and reported instead of being
/// silently dropped by the halfedge structure.
struct MeshSoup {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;     ///< polygons are ear-clipped on read
  std::vector<Eigen::Vector2d> uv;                ///< per triangle corner (3 per triangle), or empty
  std::string texture;                            ///< absolute path of the material's map_Kd, or empty
  Image texture_image;                            ///< the texture itself when the file embeds it (glTF), or empty
  std::vector<Eigen::Vector3f> colors;            ///< per point, RGB in [0, 1], when the file has vertex colours; else empty
  int polygons_triangulated = 0;                  ///< input faces with more than three corners
};

/// Reads OBJ (with uv and the MTL's map_Kd), OFF, PLY or STL through OpenMesh's readers (glTF through
/// gltf_io.h, its uv and embedded texture included), with the
/// vertex colours the file has (PLY red/green/blue properties, COFF, OBJ `v x y z r g b`).
/// \throw InputError when the file is missing, empty, unreadable or of an unknown format.
MeshSoup read_mesh_soup(const std::string& path);

struct EdgeTable;

/// Per soup point, whether a triangle uses it (corners must be in range): build_mesh keeps those
/// points only, in order.
std::vector<char> used_points(const MeshSoup& soup);

/// Builds the halfedge mesh from a soup that passed validation (see validate_mesh.h).
/// Texture coordinates, when present, are stored per halfedge. `table`, when given, is the soup's
/// edge table as validate_mesh made it (the soup unchanged since), saving building it again.
Mesh build_mesh(const MeshSoup& soup, const EdgeTable* table = nullptr);

/// The triangle list of a built mesh, e.g. to validate a mesh the pipeline produced.
MeshSoup mesh_to_soup(const Mesh& mesh);

/// Validates and builds a mesh from arrays (V: n x 3 positions, F: m x 3 vertex indices, uv: empty or
/// 3m x 2, per corner in F's order), as load_mesh does for a file: vertex i of the result is V's row
/// i, face f is F's row f (its corners turned, or flipped when its part was inside out). `what`
/// names the arrays in messages.
/// \throw InputError for what load_mesh refuses, and for vertices no
/// face uses (they would shift the indices of the rest).
Mesh mesh_from_arrays(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::MatrixX2d& uv = {},
                      const std::string& what = "the mesh");

/// Writes OBJ (with uv and an MTL naming `texture` when the mesh has uv), PLY, OFF, STL or glTF (.glb,
/// .gltf: uv and the PNG `texture` embedded, gltf_io.h), chosen by extension; OBJ, OFF and PLY keep every
/// double, STL and glTF hold float (write_positions.h). Written atomically: a failure leaves nothing.
void write_mesh(const Mesh& mesh, const std::string& path, const std::string& texture = "");

/// Writes `mesh` as binary PLY with a colour per vertex (`colors`, RGB in [0, 1], clamped and
/// rounded to uchar red, green, blue properties), atomically.
/// \throw InputError when `path` is not
/// .ply or the colour count differs from the vertex count.
void write_colored_ply(const Mesh& mesh, const std::vector<Eigen::Vector3f>& colors, const std::string& path);

/// Helpers used throughout the pipeline.
inline Eigen::Vector3d point(const Mesh& m, Mesh::VertexHandle v) {
  const auto& p = m.point(v);
  return {p[0], p[1], p[2]};
}
Eigen::MatrixX3d vertex_matrix(const Mesh& mesh);          ///< V x 3
Eigen::MatrixX3i face_matrix(const Mesh& mesh);            ///< F x 3
double bounding_box_diagonal(const Mesh& mesh);
void bounding_box(const Mesh& mesh, Eigen::Vector3d& lo, Eigen::Vector3d& hi);

}  // namespace sdm
