#include "libsdm/pose/deform_decoded.h"

#include "libsdm/pose/smooth_pose_weights.h"
#include "libstm/core/parallel.h"

#include <algorithm>

namespace sdm {
namespace {

// A unit dual quaternion real + eps dual: the rotation `real`, then the translation
// 2 dual conj(real).
struct DualQuaternion {
  Eigen::Vector4d real = Eigen::Vector4d::Zero(), dual = Eigen::Vector4d::Zero();  // (x, y, z, w)
};

Eigen::Quaterniond as_quaternion(const Eigen::Vector4d& c) { return Eigen::Quaterniond(c[3], c[0], c[1], c[2]); }

DualQuaternion dual_quaternion(const RigidMotion& m) {
  const Eigen::Quaterniond t(0, m.translation.x(), m.translation.y(), m.translation.z());
  DualQuaternion q;
  q.real = m.rotation.coeffs();
  q.dual = 0.5 * (t * m.rotation).coeffs();
  return q;
}

// The blend, normalised, as a rigid motion.
RigidMotion to_motion(const DualQuaternion& b) {
  const double norm = b.real.norm();
  const Eigen::Quaterniond real = as_quaternion(b.real / norm), dual = as_quaternion(b.dual / norm);
  RigidMotion m;
  m.rotation = real;
  m.translation = 2 * (dual * real.conjugate()).vec();
  return m;
}

// The bones' dual quaternions, each sign-aligned to the one of the bone carrying its head (q and
// -q are the same motion): at a half turn between neighbours (dot 0) the per-point alignment
// would otherwise pick either way round by rounding, and the two sides of a joint would blend
// through opposite quarter turns (a capsule twisted 180 degrees crossed itself there).
std::vector<DualQuaternion> aligned_bones(const SkeletonPose& pose) {
  const size_t nodes = pose.node_parent.size();
  std::vector<int> bone_to(nodes, -1), depth(nodes, 0);
  for (size_t k = 0; k < pose.bones.size(); ++k)
    if (pose.node_parent[size_t(pose.bones[k].tail)] == pose.bones[k].head) bone_to[size_t(pose.bones[k].tail)] = int(k);
  for (size_t n = 0; n < nodes; ++n)
    for (int u = int(n); pose.node_parent[size_t(u)] >= 0; u = pose.node_parent[size_t(u)]) ++depth[n];
  std::vector<int> order(pose.bones.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = int(k);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return depth[size_t(pose.bones[size_t(a)].head)] < depth[size_t(pose.bones[size_t(b)].head)]; });
  std::vector<DualQuaternion> dq(pose.bones.size());
  for (int k : order) {
    dq[size_t(k)] = dual_quaternion(pose.bones[size_t(k)].motion);
    const int above = bone_to[size_t(pose.bones[size_t(k)].head)];
    if (above >= 0 && dq[size_t(k)].real.dot(dq[size_t(above)].real) < 0) dq[size_t(k)].real *= -1, dq[size_t(k)].dual *= -1;
  }
  return dq;
}

}  // namespace

void deform_points(const SkeletonPose& pose, const PoseWeights& weights, std::vector<Eigen::Vector3d>& points) {
  std::vector<DualQuaternion> bone_dq = aligned_bones(pose);
  parallel_for(int(points.size()), 4096, [&](int i) {
    const int from = weights.start[size_t(i)], to = weights.start[size_t(i) + 1];
    Eigen::Vector3d x = points[size_t(i)];
    const Eigen::Vector3d& c = weights.location[size_t(i)];
    // Radius scale and stretch, blended linearly (both are 1 and nothing in most poses).
    double f = 0;
    for (int e = from; e < to; ++e) f += weights.weight[size_t(e)] * pose.bones[size_t(weights.segment[size_t(e)])].radius_scale;
    x = c + f * (x - c);
    Eigen::Vector3d stretched = Eigen::Vector3d::Zero();
    for (int e = from; e < to; ++e) {
      const Bone& b = pose.bones[size_t(weights.segment[size_t(e)])];
      stretched += weights.weight[size_t(e)] * b.stretched(x, pose.rest[size_t(b.head)]);
    }
    x = stretched;
    if (to - from == 1) {
      points[size_t(i)] = pose.bones[size_t(weights.segment[size_t(from)])].motion(x);
      return;
    }
    int heaviest = from;
    for (int e = from; e < to; ++e)
      if (weights.weight[size_t(e)] > weights.weight[size_t(heaviest)]) heaviest = e;
    const Eigen::Vector4d& pivot = bone_dq[size_t(weights.segment[size_t(heaviest)])].real;
    DualQuaternion blend;
    for (int e = from; e < to; ++e) {
      const DualQuaternion& q = bone_dq[size_t(weights.segment[size_t(e)])];
      const double w = q.real.dot(pivot) < -1e-9 ? -weights.weight[size_t(e)] : weights.weight[size_t(e)];
      blend.real += w * q.real;
      blend.dual += w * q.dual;
    }
    points[size_t(i)] = to_motion(blend)(x);
  });
}

void pose_points(const Layout& layout, const PosedSkeleton& posed, const std::vector<int>& point_segment, const Eigen::MatrixX3i& triangles,
                 std::vector<Eigen::Vector3d>& points, double blend_radii) {
  const SkeletonPose pose = pose_skeleton(layout.skeleton, posed);
  if (pose.identity()) return;
  PoseWeights weights = pose_weights(layout, points, point_segment, blend_radii);
  smooth_pose_weights(weights, points, triangles, pose, layout);
  deform_points(pose, weights, points);
}

}  // namespace sdm
