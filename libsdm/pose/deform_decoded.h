#pragma once
/// Posing decoded points (DECISIONS 4, "Posing"): each point, decoded at rest, is first pushed away
/// from its location on its segment's axis by the blended radius scale, stretched along the bones by
/// the blended stretch, then moved by the dual quaternion blend (Kavan et al. 2007, "Skinning with
/// dual quaternions": sign-aligned to the heaviest bone's, normalised) of its bones' rigid motions
/// (pose_skeleton.h) with its weights (pose_weights.h). A point with one bone moves rigidly with it;
/// a blend of rotations about a common joint stays a rotation about it (no candy wrapper, and a bend
/// keeps the cross-section).
#include "libsdm/pose/pose_skeleton.h"
#include "libsdm/pose/pose_weights.h"

#include <Eigen/Dense>
#include <vector>

namespace sdm {

/// Moves `points` (rest positions, the ones `weights` was computed for) in place.
void deform_points(const SkeletonPose& pose, const PoseWeights& weights, std::vector<Eigen::Vector3d>& points);

/// All of it: the pose of `posed` against the layout's skeleton, the weights (pose_weights, smoothed
/// over `triangles`, the surface of `points`, where motions differ: smooth_pose_weights.h), the
/// deformation.
/// \throw InputError when the graphs differ (pose_skeleton).
void pose_points(const Layout& layout, const PosedSkeleton& posed, const std::vector<int>& point_segment, const Eigen::MatrixX3i& triangles,
                 std::vector<Eigen::Vector3d>& points, double blend_radii = kPoseBlendRadii);

}  // namespace sdm
