#pragma once
/// Inner medial poles of a closed triangle mesh by the shrinking-ball method (Ma et al. 2012): for
/// every vertex, the centre of the largest ball inside the volume that touches the surface at the
/// vertex. Used to anchor the contraction to the medial axis, so that it neither drifts nor
/// swallows short limbs.
#include "libstm/geometry/triangle_bvh.h"

#include <Eigen/Dense>
#include <vector>

namespace sdm {

/// The poles one vertex at a time, so that several threads can share the work (each vertex is
/// independent of the others). V: n x 3, F: m x 3, closed; orientation may be either way (the
/// inside is found from the signed volume). Radii are capped at half the bounding-box diagonal.
/// Deterministic; commutes with rigid motions.
class MedialPoles {
 public:
  /// `surface`, when given, is a BVH over exactly V and F that the caller keeps alive (the
  /// skeleton builds one anyway; building it twice cost a millisecond before the threads start).
  MedialPoles(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const TriangleBvh* surface = nullptr);
  MedialPoles(const MedialPoles&) = delete;
  MedialPoles& operator=(const MedialPoles&) = delete;
  int size() const { return int(V_.rows()); }
  Eigen::Vector3d pole(int i) const;  ///< safe to call from several threads

 private:
  Eigen::MatrixX3d V_, N_;  ///< vertices and their area-weighted normals
  std::vector<double> reach_;  ///< longest edge at each vertex
  double inward_ = -1, r_max_ = 0, eps_ = 0;
  TriangleBvh own_;
  const TriangleBvh* bvh_;
};

/// All n poles (n x 3 ball centres).
Eigen::MatrixX3d medial_poles(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

/// `steps` steps of umbrella smoothing of the poles (row i: the pole of vertex i) over the mesh's
/// connectivity F: each pole moves halfway to the mean of its neighbours' poles. The poles scatter
/// where the surface is noisy or flat; a few steps tidy them before a surgery.
Eigen::MatrixX3d smooth_poles(const Eigen::MatrixX3d& poles, const Eigen::MatrixX3i& F, int steps);

}  // namespace sdm
