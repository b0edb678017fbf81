#pragma once
/// Packing the segment rectangles into one square atlas (paper 3.2, DESIGN 4.4).
#include <Eigen/Dense>
#include <vector>

namespace sdm {

struct PackedRect {
  int x = 0, y = 0;  ///< inner rectangle's lower-left corner in atlas texels (its margin lies around it)
  int w = 0, h = 0;  ///< inner size in texels: floor(s * size), sizes rounded to 2^-30 of the largest
                     ///< (or more once grown, see pack_rectangles)
  bool rotated = false;  ///< false: w runs along atlas x and h along atlas y; true: swapped
};

struct Packing {
  std::vector<PackedRect> rects;  ///< in input order
  double scale = 0;               ///< s: texels per input unit, the same for every rectangle before growth
  /// Packed area over atlas area. `coverage` counts each rectangle with its margin (the paper's
  /// measure: its margins lie inside the rectangles); `coverage_inner` counts the inner part only.
  double coverage = 0;
  double coverage_inner = 0;
};

/// Finds the largest global scale s (binary search) for which all rectangles, each of inner size
/// floor(s * size) texels plus `margin` texels on every side, fit into the atlas_size^2 square
/// without overlap. Placement: guillotine k-d tree (free rectangles split by each placement);
/// several sort orders, split rules, fit scores and orientation policies are tried for every s and
/// the first that fits is kept. Rotation by 90 degrees is allowed. Deterministic.
/// Then, when max_anisotropy > 1, every rectangle grows into the free space next to it (all four
/// sides, in rounds, rectangles in input order) as long as its two growth factors (final / packed
/// inner size along each side) stay within max_anisotropy of each other and under 1.9: leftover
/// strips become texels of their neighbours at a bounded, uniform distortion of those segments'
/// maps. Of the packings that fit at the final scale (at least the first 8, more for few
/// rectangles), the one that covers most once grown is kept.
/// \throw InputError when sizes are not positive and finite, or when not even a 1-texel inner
/// rectangle per input fits.
Packing pack_rectangles(const std::vector<Eigen::Vector2d>& sizes, int atlas_size, int margin, double max_anisotropy = 1.0);

}  // namespace sdm
