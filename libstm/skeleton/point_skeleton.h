#pragma once
/// The curve skeleton of a point cloud (Cao, Tagliasacchi et al. 2010, "Point cloud skeletons via
/// Laplacian-based contraction"): the cloud, or an even subsample of it, contracted on its kNN graph
/// (contract_points.h); farthest-point sampling of the contracted points into nodes, each point
/// keeping its node; edges where the one-rings join two nodes; then, as in the paper, triangles
/// collapsed along their shortest edge. Two clean-ups follow, the roles of the mesh path's surgery
/// and refinement: a cycle is kept only when it is longer than the circumference of the tube around
/// it (a handle encloses a hole wider than its own section; the web of nodes a flat part contracts
/// into does not), measured at the contracted places or, for a fat ring the contraction drew
/// towards its hole, at its points' centroids with its disc crossing the points; and end branches
/// shorter than their junction's radius are merged into it.
#include "libstm/core/progress.h"
#include "libstm/skeleton/contract_points.h"
#include "libstm/skeleton/skeleton.h"

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace sdm {

struct PointSkeletonOptions {
  /// Clouds with more points are contracted through an even subsample of about this many (each
  /// point then takes its nearest sample's node); 0: never.
  int max_samples = 10000;
  PointContractOptions contraction;
  SparseSolver solver = SparseSolver::supernodal;
  double node_spacing = 0.02;  ///< farthest-point sampling radius of the nodes, a fraction of the diagonal
  double prune_radius = 1.0;   ///< end branches shorter than this multiple of their junction's radius go
};

struct PointSkeletonStats {
  int samples = 0;              ///< points contracted
  int iterations = 0;
  double area_ratio = 1;        ///< the contraction's last area ratio
  int sampled_nodes = 0;        ///< nodes of the farthest-point sampling, before the clean-ups
  int collapsed_triangles = 0;
  int dropped_cycles = 0;       ///< edges closing a cycle shorter than its tube's circumference
  int pruned_branches = 0;
  double seconds = 0, contraction_seconds = 0, sampling_seconds = 0, graph_seconds = 0;
};

/// The skeleton of `points` (distinct, as prepare_cloud leaves them): nodes, edges, and per point
/// its node (vertex_node, one entry per point). Every node owns at least one point.
Skeleton point_cloud_skeleton(const std::vector<Eigen::Vector3d>& points, const PointSkeletonOptions& options = {},
                              const Progress& progress = nullptr, PointSkeletonStats* stats = nullptr);

/// Per node, the mean distance from the points it owns to the nearest of its segments (to the
/// node itself when it has no edge): the radius of the tube the points form around the skeleton.
std::vector<double> node_radii(const Skeleton& s, const std::vector<Eigen::Vector3d>& points);

}  // namespace sdm
