#pragma once
/// Which base face a segment's texel is encoded for, and the point of the flat base face it aims at
/// (DESIGN 4.8). The decoder places a point of a base face on the ray through that point of the
/// face's reference triangle (the face drawn on its segment's capsule, corners at the capsule's
/// radius), so a texel whose ray crosses a reference triangle is the texel that face will read;
/// texels between faces and around the segment's region are read by bilinear lookups near the
/// region's border and aim at the nearest reference triangle; texels farther than 4 texels from
/// every reference triangle are read by no face.
///
/// Shared by the encoder (which searches the surface near the target) and the decoder of quantised
/// maps (which adds the stored residual to the target's foot on the ray, the same prediction).
#include "libsdm/map/base_mesh_record.h"
#include "libstm/layout/layout.h"
#include "libstm/geometry/capsule_ray.h"
#include "libstm/geometry/triangle_bvh.h"

#include <optional>

namespace sdm {

class TexelTargets {
 public:
  /// corners: per base face, its three corners in model space (the encoder's input positions, or
  /// the decoder's placed corners). Keeps references to base and corners.
  TexelTargets(const Layout& layout, const BaseMesh& base, const std::vector<std::array<Eigen::Vector3d, 3>>& corners, int segment);

  struct Target {
    int base_face = -1;
    Eigen::Vector3d bary, point;  ///< point = the flat base face's point at bary
    double foot = 0;              ///< point projected on the ray (the prediction of D)
  };
  /// The target of the texel whose ray this is; nothing when no base face reads it.
  std::optional<Target> target(const CapsuleRay& ray) const;

  const CapsuleFrame& frame() const { return frame_; }
  const std::vector<int>& faces() const { return faces_; }  // the segment's base faces

 private:
  const BaseMesh& base_;
  const std::vector<std::array<Eigen::Vector3d, 3>>& corners_;
  const LayoutSegment& seg_;
  CapsuleFrame frame_;
  std::vector<int> faces_;
  Eigen::MatrixX3d R_;  ///< corners of the segment's base faces on the reference capsule
  TriangleBvh reference_;
  double texel_ = 0;
};

}  // namespace sdm
