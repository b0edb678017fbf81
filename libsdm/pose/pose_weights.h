#pragma once
/// Blend weights of decoded points over the skeleton's segments (DECISIONS 4, "Posing"): a point of
/// segment s sits at its location, the closest point of s's axis clamped to the segment; its
/// distance to another segment k is the distance along the skeleton from that location to k's
/// nearest end node (through the graph, Dijkstra bounded by the kernel's reach); its weight on k is
/// K(d / h), K(t) = (1 - t^2)^2 for t < 1 and 0 beyond, h = beta times the smaller of the two
/// segments' radii, and 1 on s itself; the weights are normalised. A point farther than h along the
/// skeleton from every other segment has weight 1 on its own and moves rigidly with it.
#include "libsdm/pose/pose_skeleton.h"
#include "libstm/layout/layout.h"

#include <Eigen/Dense>
#include <array>
#include <vector>

namespace sdm {

/// The kernel width in radii, chosen by the pose tests (tests/test_pose.cpp).
constexpr double kPoseBlendRadii = 1.2;
constexpr double kPoseStrayRadii = 1.5;

struct PoseWeights {
  std::vector<int> start;               ///< point i's entries are [start[i], start[i + 1])
  std::vector<int> segment;             ///< per entry: the segment
  std::vector<double> weight;           ///< per entry: its weight (a point's sum to 1)
  std::vector<Eigen::Vector3d> location;  ///< per point: its location on its own segment's axis
  std::vector<int> own;                   ///< per point: its own segment (see pose_weights)
};

/// Weights of `points` (rest positions, e.g. a decode's), each on segment point_segment[i] of
/// `layout` (a decode's DecodeTrace::vertex_segment), the layout's rest skeleton and radii. A point
/// farther than kPoseStrayRadii of its segment's radii from the segment's axis takes as its own the
/// segment nearest it in radii instead: its base face came from input faces the skeleton gave to a
/// distant node, and moved with that node it would be a spike out of the posed surface
/// (BENCHMARKS "Posing through the skeleton").
/// \throw std::invalid_argument when the sizes differ or a segment index is out of range.
PoseWeights pose_weights(const Layout& layout, const std::vector<Eigen::Vector3d>& points, const std::vector<int>& point_segment,
                         double blend_radii = kPoseBlendRadii);

/// The weights as a rigged mesh's skin wants them (glTF: 4 joints per vertex): joints are skeleton
/// nodes, each segment's weight given to the node at its head (the bone's parent end, pose.bones),
/// summed over segments sharing a head, the 4 largest kept and renormalised (unused slots: joint 0,
/// weight 0). node_parent: the bone tree (pose.node_parent, -1 for a root).
struct RigWeights {
  std::vector<int> node_parent;
  std::vector<std::array<int, 4>> joints;
  std::vector<std::array<float, 4>> weights;
};
RigWeights rig_weights(const SkeletonPose& pose, const PoseWeights& weights);

}  // namespace sdm
