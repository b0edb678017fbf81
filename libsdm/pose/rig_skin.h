#pragma once
/// A decoded mesh's glTF skin (DECISIONS 4, "Posing"; glTF 2.0 "Skins"): the decode's own blending
/// (pose_weights.h) as 4 joints per vertex (rig_weights), one joint per skeleton node at its rest
/// position, parented by the bone tree rooted at the largest junction (pose_skeleton.h), so that
/// Blender, three.js or a game engine pose the decoded mesh by linear blend skinning.
#include "libsdm/pose/pose_skeleton.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/gltf_skin.h"

#include <Eigen/Core>
#include <vector>

namespace sdm {

/// The skin of `points` (a decode at rest: the layout's own skeleton; one per mesh vertex, `triangles`
/// its faces), each on segment point_segment[i] (DecodeTrace::vertex_segment), with the weights
/// smoothed across the segments' borders (smooth_rig_weights). Joints: the layout's skeleton nodes, named
/// "node N", at their rest positions; parents: the bone tree. When `posed` is given (a pose of the
/// layout's skeleton, as sdm pose takes it), the joints also get that pose (joint_pose_rotation and
/// joint_pose_position): each node's posed position, and the rotation of the bone it heads when it
/// heads one bone, else the node's rotation (pose_skeleton). Linear blend skinning with one rotation
/// per node honours rigid turns of sub-trees exactly away from the joints; stretch, radius scales and
/// different swings of the bones leaving one junction are not carried by a glTF skin.
/// \throw InputError when `posed` has another graph than the layout's skeleton, std::invalid_argument
/// when the sizes differ or a segment is out of range (pose_weights).
GltfSkin rig_skin(const Layout& layout, const std::vector<Eigen::Vector3d>& points, const std::vector<int>& point_segment,
                  const Eigen::MatrixX3i& triangles, const PosedSkeleton* posed = nullptr);

}  // namespace sdm
