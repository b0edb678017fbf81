#include "libsdm/map/texels.h"

namespace sdm {

Eigen::Vector2d texel_local_uv(const LayoutSegment& seg, int ix, int iy) {
  const double X = ix + 0.5 - seg.x, Y = iy + 0.5 - seg.y;
  return seg.rotated ? Eigen::Vector2d(X, Y) : Eigen::Vector2d(Y, X);
}

double sample_displacement(const SdmImage& im, const LayoutSegment& seg, double u, double v) {
  return sample_texels(seg, u, v, [&](int ix, int iy) { return double(im.D[texel_index(im, ix, iy)]); });
}

}  // namespace sdm
