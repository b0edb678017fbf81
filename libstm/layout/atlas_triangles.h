#pragma once
/// Mesh faces placed in a layout's atlas (DESIGN 4.7), unwrapped across the capsules' seams.
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"

#include <Eigen/Dense>
#include <array>
#include <vector>

namespace sdm {

/// One triangle as drawn into the atlas: texel coordinates of its corners, unwrapped across the
/// phi = 0 seam so that it spans less than half its rectangle around the axis (when it can: a
/// triangle around a pole keeps its corners' angles). A seam triangle (reaching past either end
/// of its rectangle's u range) comes twice: copy 0 as in stm_coordinates, copy 1 shifted by h the
/// other way, so both sides of the seam are filled once each copy is clipped to the rectangle.
struct AtlasTriangle {
  int face = -1, segment = -1, copy = 0;
  std::array<Eigen::Vector2d, 3> atlas;   ///< texels
  std::array<Eigen::Vector2d, 3> local;   ///< (u, v) in the segment's rectangle, unwrapped
};

/// The faces of `mesh` in the atlas, face by face (a seam face's two copies one after the other).
/// \throw InputError when face_segment has not one entry per face or names no segment of the layout.
std::vector<AtlasTriangle> atlas_triangles(const Mesh& mesh, const Layout& layout, const std::vector<int>& face_segment);

}  // namespace sdm
