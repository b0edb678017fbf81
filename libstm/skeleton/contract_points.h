#pragma once
/// Laplacian contraction of a point cloud (Cao, Tagliasacchi et al. 2010, "Point cloud skeletons via
/// Laplacian-based contraction", section 4): the mesh contraction of contract_mesh.h on the local
/// Delaunay one-rings of the points (local_delaunay.h) instead of faces. Each iteration takes the
/// cotangent weights of the rings' triangles at the current positions (clamped, with a uniform part
/// as proxy_contraction adds) and the attraction W_H,i = sqrt(A_i^0 / A_i) of the ring areas.
#include "libstm/core/progress.h"
#include "libstm/skeleton/contract_mesh.h"

#include <Eigen/Dense>
#include <vector>

namespace sdm {

struct PointContractOptions {
  int neighbours = 16;            ///< k of the local triangulation (Cao et al.'s default)
  double laplacian_weight = 0.1;  ///< W_L0 = this * sqrt(points) (Au et al.'s rule as contract_mesh takes it)
  double laplacian_scale = 2;     ///< s_L: W_L times this each iteration
  double max_laplacian_growth = 32;  ///< W_L stops growing at this multiple of W_L0 (beyond, whole limbs are pulled into the body)
  double max_attraction = 1e4;    ///< W_H,i clamped to this
  double cot_max = 5;             ///< cotangents clamped to [0, cot_max]
  double uniform_blend = 0.5;     ///< added to every triangle's cotangent weight
  double area_ratio_stop = 1e-3;  ///< stop when the rings' area falls below this fraction of the start's
  int max_iterations = 20;
};

struct PointContractResult {
  Eigen::MatrixX3d positions;           ///< contracted, one row per point, in input units
  std::vector<std::vector<int>> rings;  ///< the one-ring of every point, both ways (sorted, without itself)
  std::vector<double> area_ratio;       ///< the rings' area over the start's, after each iteration
  int iterations = 0;
  double factor_seconds = 0;
};

/// Contracts `points` (at least 4). Each iteration solves (L^T W_L^2 L + W_H^2) P' = W_H^2 P, then
/// updates W_H and grows W_L, until the area ratio, the iteration count or stagnation (an
/// iteration at the largest W_L that no longer halves the area) stops it. Deterministic.
PointContractResult contract_points(const std::vector<Eigen::Vector3d>& points, const PointContractOptions& options = {},
                                    SparseSolver solver = SparseSolver::supernodal, const Progress& progress = nullptr);

}  // namespace sdm
