#pragma once
/// The pairing step of a non-rigid ICP (Amberg et al. 2007), shared by the articulated registration
/// and fit_skeleton: closest points both ways between a moving surface and a fixed target.
#include "libstm/core/parallel.h"
#include "libstm/geometry/triangle_bvh.h"

#include <Eigen/Dense>
#include <algorithm>
#include <vector>

namespace sdm {

/// Pairs of the moving surface (its points `moved`, faces F) and the target (`target_bvh` over its
/// faces, `target_points` its vertices), every stride-th point either way: first one per moving
/// point v, `on_moved(pair, v, closest point of the target)`, then one per target point j,
/// `on_target(pair, j, closest point of the moved surface)`, in that order. `hints` (moved +
/// target counts, -1 at first) carry each query's face from one call to the next
/// (TriangleBvh::closest_point_near: the same faces as without them). The queries run on two
/// threads where a core is free: the callbacks may write only the pair they are given.
template <class Pair, class OnMoved, class OnTarget>
std::vector<Pair> closest_pairs_both_ways(const TriangleBvh& target_bvh, const std::vector<Eigen::Vector3d>& moved,
                                          const Eigen::MatrixX3i& F, const std::vector<Eigen::Vector3d>& target_points,
                                          std::vector<int>& hints, int stride, const OnMoved& on_moved,
                                          const OnTarget& on_target) {
  stride = std::max(stride, 1);
  const int ns = int(moved.size()), nt = int(target_points.size());
  hints.resize(size_t(ns + nt), -1);
  Eigen::MatrixX3d V(ns, 3);
  for (int v = 0; v < ns; ++v) V.row(v) = moved[size_t(v)].transpose();
  const TriangleBvh moved_bvh(V, F);
  const int from_moved = (ns + stride - 1) / stride, from_target = (nt + stride - 1) / stride;
  std::vector<Pair> pairs(size_t(from_moved + from_target));
  parallel_for(from_moved + from_target, 512, [&](int i) {
    if (i < from_moved) {
      const int v = i * stride;
      on_moved(pairs[size_t(i)], v, target_bvh.closest_point_near(moved[size_t(v)], hints[size_t(v)]));
    } else {
      const int j = (i - from_moved) * stride;
      on_target(pairs[size_t(i)], j, moved_bvh.closest_point_near(target_points[size_t(j)], hints[size_t(ns + j)]));
    }
  }, 2);
  return pairs;
}

}  // namespace sdm
