#pragma once
// Skeleton displacement map encoding (paper 5, DESIGN 4.8): for every texel of every segment's
// rectangle, a distance along the texel's capsule ray (capsule_ray.h) to the surface (D, model
// units) and whether that crossing lies on the segment's own faces (A). The layout and the base
// mesh (base_mesh.h) travel in the header, so the file alone rebuilds the surface.
//
// D is not simply the first crossing: the decoder places each point of a base face on the ray
// through the same point of the face's reference triangle (the face drawn on the segment's
// capsule), so each texel is encoded for the base face its ray passes through (or the nearest one,
// for texels between and around them): D is the crossing nearest the point of that flat base face,
// or, when no crossing is within half the face's longest edge (a ray grazing a saddle), that
// point's foot on the ray. Near junctions the first crossing is often another sheet of the surface.
#include "libstm/core/progress.h"
#include "libsdm/map/sdm_exr.h"
#include "libstm/layout/layout.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace sdm {

struct EncodeOptions {
  int base_vertices = 0;  // size of the base mesh (0: chosen from the mesh)
  Progress progress;
  // Texels no base face reads: the first crossing of their ray with the segment's faces (else any),
  // for pictures of the map (`sdm encode --png`); false leaves them NaN, as every file stores and
  // every reader sees them (format 3), and saves two ray casts each: `sdm encode` of a 30k-vertex
  // mesh at 1024, encode stage 2.70-2.83 -> 2.27-2.41 s, the file byte for byte the same.
  bool fill_unread = true;
};

struct EncodeStats {
  long texels = 0;      // texels inside the segments' rectangles
  long own_hits = 0;    // A = 1: D is a crossing with the segment's own faces
  long other_hits = 0;  // A = 0, D is a crossing with another segment's faces
  long filled = 0;      // A = 0, D is the foot of the base face's point (no crossing near it)
  int base_faces = 0;
};

// Texels outside every rectangle get D = 0, A = 0. The layout must have been computed for `mesh`.
SdmImage encode_sdm(const Mesh& mesh, const Layout& layout, const EncodeOptions& options = {}, EncodeStats* stats = nullptr);

// The (u, v) of the centre of a segment's texel (ix, iy are atlas texel indices inside the
// rectangle), and the D lookup used by the decoder: bilinear between texel centres, periodic
// around the axis, clamped along it, NaN texels (left out of a compact map) skipped; NaN when the
// four texels are all left out. Shared so encoder, decoder and tests agree on texel centres.
Eigen::Vector2d texel_local_uv(const LayoutSegment& seg, int ix, int iy);
// Atlas texel (ix, iy) (origin lower left) -> index into the image's channels (rows top to bottom).
inline size_t texel_index(const SdmImage& im, int ix, int iy) {
  return size_t(im.height - 1 - iy) * size_t(im.width) + size_t(ix);
}
double sample_displacement(const SdmImage& image, const LayoutSegment& seg, double u, double v);

// The same lookup over any texel source: texel(ix, iy) gives the value of atlas texel (ix, iy)
// (origin lower left), NaN for a texel left out.
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
