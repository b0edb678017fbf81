#pragma once
/// Where a map's texels are and how a point reads them: shared by the encoder, the decoder and the
/// tests so that they agree on texel centres, periodicity around the axis and left-out texels.
#include "libsdm/map/sdm_exr.h"
#include "libstm/layout/layout.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace sdm {

/// The (u, v) of the centre of a segment's texel (ix, iy are atlas texel indices inside the
/// rectangle), and the D lookup used by the decoder: bilinear between texel centres, periodic
/// around the axis, clamped along it, NaN texels (left out of a compact map) skipped; NaN when the
/// four texels are all left out. Shared so encoder, decoder and tests agree on texel centres.
Eigen::Vector2d texel_local_uv(const LayoutSegment& seg, int ix, int iy);
/// Atlas texel (ix, iy) (origin lower left) -> index into the image's channels (rows top to bottom).
inline size_t texel_index(const SdmImage& im, int ix, int iy) {
  return size_t(im.height - 1 - iy) * size_t(im.width) + size_t(ix);
}
double sample_displacement(const SdmImage& image, const LayoutSegment& seg, double u, double v);

/// The same lookup over any texel source: texel(ix, iy) gives the value of atlas texel (ix, iy)
/// (origin lower left), NaN for a texel left out.
template <class Texel>
double sample_texels(const LayoutSegment& seg, double u, double v, const Texel& texel) {
  // Continuous texel coordinates in the rectangle: centres at i + 0.5.
  const double fu = u - 0.5, fv = std::clamp(v - 0.5, 0.0, double(seg.w - 1));
  const double u0 = std::floor(fu), v0 = std::floor(fv);
  const double au = fu - u0, av = fv - v0;
  auto at = [&](long iu, long iv) {
    iu = ((iu % seg.h) + seg.h) % seg.h;
    iv = std::clamp<long>(iv, 0, seg.w - 1);
    return seg.rotated ? texel(seg.x + int(iu), seg.y + int(iv)) : texel(seg.x + int(iv), seg.y + int(iu));
  };
  const long iu = long(u0), iv = long(v0);
  // Texels a compact map leaves out are skipped and the others' weights renormalised.
  double sum = 0, weight = 0;
  for (int k = 0; k < 4; ++k) {
    const double w = (k & 1 ? au : 1 - au) * (k & 2 ? av : 1 - av), d = at(iu + (k & 1), iv + (k >> 1));
    if (!std::isnan(d) && w > 0) sum += w * d, weight += w;
  }
  return weight > 0 ? sum / weight : NAN;
}

}  // namespace sdm
