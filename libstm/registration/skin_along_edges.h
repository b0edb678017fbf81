#pragma once
/// The two-node blend a registration moves a surface point with (articulated_registration.h,
/// fit_skeleton.h): the two ends of the skeleton edge the point lies along.
#include "libstm/skeleton/skeleton.h"

#include <Eigen/Dense>
#include <vector>

namespace sdm {

/// A point's blend of node maps: w[0] of node[0] (its own node) and w[1] of node[1]; they sum to 1.
struct EdgeSkin {
  int node[2] = {0, 0};
  double w[2] = {1, 0};
};

/// Every point blended between its node (skeleton.vertex_node) and the neighbour whose edge passes
/// nearest to it, the weights by the point's position along that edge clamped to it; a node without
/// neighbours keeps its points alone. `points` and `nodes` in one frame; `adjacency` is
/// skeleton.adjacency() (passed in, as the callers keep it).
/// \pre skeleton.vertex_node has an entry per point, each an index into `nodes` and `adjacency`.
std::vector<EdgeSkin> skin_along_edges(const Skeleton& skeleton, const std::vector<Eigen::Vector3d>& points,
                                       const std::vector<Eigen::Vector3d>& nodes, const std::vector<std::vector<int>>& adjacency);

}  // namespace sdm
