#include "libsdm/pose/rig_skin.h"

#include "libsdm/pose/smooth_pose_weights.h"

#include <string>

namespace sdm {

GltfSkin rig_skin(const Layout& layout, const std::vector<Eigen::Vector3d>& points, const std::vector<int>& point_segment,
                  const Eigen::MatrixX3i& triangles, const PosedSkeleton* posed) {
  const Skeleton& rest = layout.skeleton;
  const SkeletonPose pose = posed ? pose_skeleton(rest, *posed) : pose_skeleton(rest, rest);
  PoseWeights weights = pose_weights(layout, points, point_segment);
  smooth_rig_weights(weights, points, triangles, layout);
  const RigWeights rig = rig_weights(pose, weights);
  GltfSkin skin;
  const size_t n = rest.nodes.size();
  for (size_t j = 0; j < n; ++j) {
    skin.joint_position.push_back(rest.nodes[j]);
    skin.joint_name.push_back("node " + std::to_string(j));
  }
  skin.joint_parent = rig.node_parent;
  skin.vertex_joints = rig.joints;
  skin.vertex_weights = rig.weights;
  if (!posed || pose.identity()) return skin;
  std::vector<int> headed(n, 0), bone(n, -1);
  for (size_t s = 0; s < pose.bones.size(); ++s) {
    ++headed[size_t(pose.bones[s].head)];
    bone[size_t(pose.bones[s].head)] = int(s);
  }
  for (size_t j = 0; j < n; ++j) {
    skin.joint_pose_position.push_back(pose.posed[j]);
    skin.joint_pose_rotation.push_back(headed[j] == 1 ? pose.bones[size_t(bone[j])].motion.rotation : pose.node_rotation[j]);
  }
  return skin;
}

}  // namespace sdm
