#pragma once
/// The bones of a posed skeleton (DECISIONS 4, "Posing"): the skeleton graph rooted at its largest
/// junction, every segment a bone carried by its parent end's motion (a glTF or Blender joint at the
/// bone's head), each node's rotation given or derived, and per bone the motion of the rest-pose
/// points along it: T(x) = B (S(x) - p) + p', with S a stretch along the bone (its posed length over
/// its rest length), B = (minimal swing taking R_p (c - p) onto c' - p') R_p, so that the posed node
/// positions are always honoured. A rigid motion of a sub-tree about one of its nodes gives every
/// bone in it exactly that motion.
#include "libstm/layout/layout.h"
#include "libstm/skeleton/posed_skeleton.h"
#include "libstm/skeleton/skeleton.h"

#include <Eigen/Geometry>
#include <vector>

namespace sdm {

/// x -> rotation x + translation.
struct RigidMotion {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d operator()(const Eigen::Vector3d& x) const { return rotation * x + translation; }
};

struct Bone {
  int head = -1, tail = -1;              ///< parent end p and child end c (nodes)
  Eigen::Vector3d direction;             ///< unit rest direction p -> c
  double length = 0;                     ///< rest length |c - p|
  double stretch = 1;                    ///< posed length over rest length
  double radius_scale = 1;               ///< PosedSkeleton::segment_radius_scale
  RigidMotion motion;                    ///< applied after the stretch: B (x - p) + p'
  /// The rest point x stretched along the bone: the part of x - p along the bone (clamped to the
  /// bone) scaled by `stretch`.
  Eigen::Vector3d stretched(const Eigen::Vector3d& x, const Eigen::Vector3d& p) const;
};

struct SkeletonPose {
  std::vector<int> node_parent;                   ///< the bone tree: parent node, -1 for a root
  std::vector<Eigen::Quaterniond> node_rotation;  ///< given or derived, from the rest pose
  std::vector<Bone> bones;                        ///< one per segment (= skeleton edge)
  std::vector<Eigen::Vector3d> rest, posed;       ///< node positions
  bool identity() const;                          ///< nothing moves
};

/// The node the skeleton's first component not yet `taken` (empty: none taken) is rooted at: the node
/// with the most incident edges; ties: the most vertices mapped (vertex_node), then the nearest to
/// the nodes' centroid. A component without a junction (a chain) is rooted at an end node (the one
/// with the most vertices mapped), so that a bend or a twist at any inner node turns one side of it.
int skeleton_root(const Skeleton& s, const std::vector<char>& taken = {});

/// The nodes below `node` in the bone tree (away from its root), `node` itself included.
std::vector<int> subtree_nodes(const SkeletonPose& pose, int node);

/// Turns the sub-tree below `node` of `posed` (a pose of `rest`; its descendants in the bone tree)
/// about node's posed position by q: their positions, and node_rotations (each node's rotation in
/// the current pose, given or derived, composed with q; all nodes get one). Repeated calls compose.
/// \throw InputError for a node out of range or a skeleton of another graph.
void rotate_subtree(const Skeleton& rest, PosedSkeleton& posed, int node, const Eigen::Quaterniond& q);

/// The bones of `posed` (the rest skeleton's graph with moved nodes, and optionally node_rotations
/// and segment_radius_scale) against `rest`. A node's rotation without one given: at a node with two
/// or more children whose offsets are not collinear and turn rigidly (the Kabsch fit of the rest onto
/// the posed directions matches each within 1e-3), that fit; else the rotation of the bone that
/// carries it (for a root: the identity), so that twist propagates down chains.
/// \throw InputError
/// when the graphs differ (another count of nodes or edges, or an edge joining other nodes).
SkeletonPose pose_skeleton(const Skeleton& rest, const PosedSkeleton& posed);

/// The rotation taking unit vector `from` onto unit vector `to` about their common perpendicular
/// (the identity for equal vectors; a half turn about some perpendicular for opposite ones).
Eigen::Quaterniond minimal_swing(const Eigen::Vector3d& from, const Eigen::Vector3d& to);

}  // namespace sdm
