#pragma once
/// Inside/outside queries against a closed triangle mesh, accelerated by the bounding-volume
/// hierarchy over its triangles of triangle_bvh.h (ray parity, segment hits). Used to keep
/// skeleton nodes and segments inside the volume.
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/mesh/mesh.h"

#include <Eigen/Dense>

namespace sdm {

class InsideMesh {
 public:
  InsideMesh() = default;
  /// `V` (n x 3) and `F` (m x 3) describe a closed, consistently oriented or not, triangle mesh;
  /// only the geometry is used (parity, not orientation).
  InsideMesh(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);
  explicit InsideMesh(const Mesh& mesh);

  /// True when p lies inside the closed surface: ray parity along three fixed directions, majority
  /// vote, so that a ray grazing an edge or a vertex does not decide alone.
  bool inside(const Eigen::Vector3d& p) const;
  /// True when the closed segment a-b meets a triangle of the surface.
  bool segment_crosses(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const;
  /// Both ends inside and no crossing: the whole segment lies inside the volume.
  bool segment_inside(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
    return inside(a) && !segment_crosses(a, b) && inside(b);
  }
  /// Triangle a, b, c meets the surface (tested as a fan of segments from c to points of a-b and
  /// the three sides; enough to tell whether a small loop spans a hole of the volume).
  bool triangle_crosses(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, int fan = 8) const;

 private:
  TriangleBvh bvh_;
};

}  // namespace sdm
