#pragma once
/// The one-ring of every point of a cloud from a local Delaunay triangulation (Cao, Tagliasacchi et
/// al. 2010, section 4.1): the point's k nearest neighbours projected onto its tangent plane (their
/// principal axes), and the neighbours whose Voronoi half-planes bound the point's cell there.
/// Consecutive ones form the point's triangles, on which cotangent weights and ring areas are taken.
#include <Eigen/Dense>

#include <array>
#include <vector>

namespace sdm {

struct LocalRings {
  std::vector<std::vector<int>> ring;                     ///< per point, its Delaunay neighbours (angular order)
  std::vector<std::vector<std::array<int, 2>>> triangles; ///< per point i, its triangles (i, a, b)
};

/// The local Delaunay one-rings of `points` from their `k` nearest neighbours (k >= 3).
LocalRings local_delaunay_rings(const std::vector<Eigen::Vector3d>& points, int k);

}  // namespace sdm
