#pragma once
/// Rigged glTF 2.0: a mesh with a skin (glTF 2.0 specification, "Skins" and "Skinned Mesh
/// Attributes"), so Blender, three.js or a game engine can pose it by linear blend skinning. The
/// joints are a node tree (each joint's translation relative to its parent, no rotation at rest),
/// the skin's inverse bind matrices the inverse of each joint's rest transform (a translation by
/// minus its position), and every vertex carries 4 joints (JOINTS_0) and 4 weights (WEIGHTS_0).
/// Written through write_gltf's code paths (gltf_io.h), so the mesh, its uv and texture are as
/// write_gltf writes them; the file follows the skin rules the Khronos glTF validator checks.
#include "libstm/mesh/gltf_io.h"
#include "libstm/mesh/mesh.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <string>
#include <vector>

namespace sdm {

struct GltfSkin {
  std::vector<Eigen::Vector3d> joint_position;       ///< rest (bind) pose, model space, one per joint
  std::vector<int> joint_parent;                     ///< per joint: its parent joint, -1 for a root
  std::vector<std::string> joint_name;               ///< per joint, or empty (then "joint 0", "joint 1", ...)
  std::vector<std::array<int, 4>> vertex_joints;     ///< per mesh vertex (per point when read): 4 joints
  std::vector<std::array<float, 4>> vertex_weights;  ///< their weights: >= 0, summing to 1
  /// Optional (both empty, or one per joint): a pose the file opens in, each joint's posed rotation
  /// and position in model space, the joint moving the rest point x to rotation (x - rest) + position.
  /// Written as the joint nodes' local rotation and translation; the bind pose (the inverse bind
  /// matrices) stays joint_position. read_gltf_skin leaves them empty.
  std::vector<Eigen::Quaterniond> joint_pose_rotation;
  std::vector<Eigen::Vector3d> joint_pose_position;
};

/// Writes `mesh` rigged by `skin` as .glb or .gltf (by extension), as write_gltf writes the mesh
/// (uv and `texture_png` included) plus: one node per joint, the joints' node tree beside the mesh's
/// node in the scene (the skinned mesh node has no transform and no parent), a skin whose
/// `skeleton` is the root joint and whose `inverseBindMatrices` (MAT4 float) translate by minus
/// each joint's position, JOINTS_0 (UNSIGNED_BYTE VEC4 for 256 joints or fewer, else
/// UNSIGNED_SHORT) and WEIGHTS_0 (FLOAT VEC4) for each written vertex (vertices split at uv seams
/// carry their mesh vertex's). With joint_pose_rotation and joint_pose_position the joint nodes hold
/// that pose (local rotation R_parent^-1 R_joint, translation R_parent^-1 (p_joint - p_parent)), so
/// the file opens posed; without, at rest. The parents may form a forest: then an untransformed node named
/// "skeleton" holds the roots and is the skin's `skeleton`.
/// Each vertex's influences are written tidied: a joint named twice gets the sum of its weights in
/// its first slot, a slot of weight 0 holds joint 0 (a slot of weight 0 may name any joint, -1
/// included), and the weights are divided by their sum, the largest then moved by float steps until
/// the float sum of the slots in order is 1 (the validator asks for exactly 1 with one or two
/// joints). Slots keep their order otherwise. Atomic.
/// \throw InputError (message saying which) for: no joints or more than 65536, parents, names or
/// per-vertex arrays of the wrong size (vertex arrays: mesh.n_vertices(); pose arrays: empty or one
/// per joint, finite), a parent out of range
/// or parents forming a cycle, a joint position that is not finite, a weight that is negative or
/// not finite, a vertex whose weights are all 0, a joint of weight > 0 outside [0, joints); and for
/// what write_gltf refuses (the path's extension, a texture that is no PNG).
void write_gltf_skinned(const Mesh& mesh, const GltfSkin& skin, const std::string& path, const std::string& texture_png = "");

/// Reads the skin of a rigged .glb or .gltf (any writer's, not only sdm's): the joints of the skin
/// that skins its meshes, in the skin's order, with their rest positions (the translation of the
/// inverse of each inverse bind matrix: the pose the mesh was bound in; the joints' global node
/// transforms where the skin has none), parents (the nearest ancestor node that is a joint, -1
/// when none) and node names; and per point of read_gltf's welded points (read_gltf welds glTF
/// vertices at the same position) the joints and weights of the first glTF vertex welded there,
/// zero-weight slots given joint 0 and the weights divided by their sum when it is not 1 within
/// 1e-6 (exporters round). `scene`, when given, receives what read_gltf returns for the file (the
/// points the weights belong to), from the same read.
/// \throw InputError naming the file and the problem for what read_gltf refuses, and for: no mesh
/// node with a skin, a mesh without a skin or skinned by another skin than the first, a skin or
/// joint naming a missing node, JOINTS_0 or WEIGHTS_0 missing, not VEC4, of a type glTF does not
/// allow there, or counting other than POSITION, more than 4 influences (JOINTS_1), an accessor
/// outside its buffer, a joint index >= the skin's joints, a weight negative or not finite, a
/// vertex whose weights are all 0, inverse bind matrices counting other than the joints or not
/// invertible, and welded duplicates whose influences differ by more than 1e-4 in any joint's
/// weight (vertices at one position that bend differently).
GltfSkin read_gltf_skin(const std::string& path, GltfScene* scene = nullptr);

}  // namespace sdm
