#pragma once
/// Area-weighted vertex normals, the one definition the stages share: per vertex, the sum of the
/// area vectors (b - a) x (c - a) of the triangles around it (each twice its triangle's area along
/// its normal), so that large triangles count more than slivers.
#include <Eigen/Dense>
#include <vector>

namespace sdm {

/// The sums, not normalised (a vertex no triangle uses keeps zero), over the triangles in order.
/// `corner(f, k)` returns the position of corner k (0, 1, 2) of triangle f: the vertex's point, or
/// a per-triangle copy of it (a decoded base face's corners).
/// \pre every index in `triangles` is in [0, vertices).
template <class Corner>
std::vector<Eigen::Vector3d> vertex_area_vectors(const Eigen::MatrixX3i& triangles, size_t vertices, const Corner& corner) {
  std::vector<Eigen::Vector3d> sum(vertices, Eigen::Vector3d::Zero());
  for (int f = 0; f < triangles.rows(); ++f) {
    const Eigen::Vector3d a = corner(f, 0);
    const Eigen::Vector3d n = (Eigen::Vector3d(corner(f, 1)) - a).cross(Eigen::Vector3d(corner(f, 2)) - a);
    for (int k = 0; k < 3; ++k) sum[size_t(triangles(f, k))] += n;
  }
  return sum;
}

/// The same for points given per vertex.
/// \pre every index in `triangles` is in [0, points.size()).
inline std::vector<Eigen::Vector3d> vertex_area_vectors(const Eigen::MatrixX3i& triangles, const std::vector<Eigen::Vector3d>& points) {
  return vertex_area_vectors(triangles, points.size(), [&](int f, int k) -> const Eigen::Vector3d& { return points[size_t(triangles(f, k))]; });
}

}  // namespace sdm
