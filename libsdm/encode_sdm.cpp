#include "libsdm/encode_sdm.h"

#include "libsdm/base_mesh.h"
#include "libstm/capsule_ray.h"
#include "libstm/segments.h"
#include "libstm/triangle_bvh.h"

#include <cmath>

namespace stm {
namespace {

// Atlas texel (ix, iy) (origin lower left) -> index into the image (rows top to bottom).
size_t pixel(const SdmImage& im, int ix, int iy) { return size_t(im.height - 1 - iy) * size_t(im.width) + size_t(ix); }

// The rectangle's extent in atlas texels: w along the axis, h around it (layout.h conventions).
void extent(const LayoutSegment& s, int& ex, int& ey) {
  ex = s.rotated ? s.h : s.w;
  ey = s.rotated ? s.w : s.h;
}

}  // namespace

Eigen::Vector2d texel_local_uv(const LayoutSegment& seg, int ix, int iy) {
  const double X = ix + 0.5 - seg.x, Y = iy + 0.5 - seg.y;
  return seg.rotated ? Eigen::Vector2d(X, Y) : Eigen::Vector2d(Y, X);
}

double sample_displacement(const SdmImage& im, const LayoutSegment& seg, double u, double v) {
  // Continuous texel coordinates in the rectangle: centres at i + 0.5.
  const double fu = u - 0.5, fv = std::clamp(v - 0.5, 0.0, double(seg.w - 1));
  const double u0 = std::floor(fu), v0 = std::floor(fv);
  const double au = fu - u0, av = fv - v0;
  auto at = [&](long iu, long iv) {
    iu = ((iu % seg.h) + seg.h) % seg.h;
    iv = std::clamp<long>(iv, 0, seg.w - 1);
    const int ix = seg.rotated ? seg.x + int(iu) : seg.x + int(iv);
    const int iy = seg.rotated ? seg.y + int(iv) : seg.y + int(iu);
    return double(im.D[pixel(im, ix, iy)]);
  };
  const long iu = long(u0), iv = long(v0);
  return (1 - au) * (1 - av) * at(iu, iv) + au * (1 - av) * at(iu + 1, iv) + (1 - au) * av * at(iu, iv + 1) +
         au * av * at(iu + 1, iv + 1);
}

SdmImage encode_sdm(const Mesh& mesh, const Layout& layout, const EncodeOptions& options, EncodeStats* stats) {
  EncodeStats st;
  SdmImage im;
  im.width = im.height = layout.size;
  im.D.assign(size_t(layout.size) * layout.size, 0.0f);
  im.A.assign(im.D.size(), 0.0f);

  const Eigen::MatrixX3d V = vertex_matrix(mesh);
  const Eigen::MatrixX3i F = face_matrix(mesh);
  const std::vector<int> face_segment = assign_faces(mesh, layout.skeleton);
  std::vector<std::vector<int>> faces_of(layout.segments.size());
  for (size_t f = 0; f < face_segment.size(); ++f) faces_of[face_segment[f]].push_back(int(f));
  const TriangleBvh all(V, F);

  for (size_t s = 0; s < layout.segments.size(); ++s) {
    const LayoutSegment& seg = layout.segments[s];
    if (options.progress && s % 8 == 0)
      options.progress("encoding segment " + std::to_string(s + 1) + "/" + std::to_string(layout.segments.size()));
    const CapsuleFrame frame = capsule_frame(layout, int(s));
    const TriangleBvh own(V, F, faces_of[s]);
    int ex, ey;
    extent(seg, ex, ey);
    std::vector<char> known(size_t(ex) * ey, 0);
    for (int j = 0; j < ey; ++j)
      for (int i = 0; i < ex; ++i) {
        const int ix = seg.x + i, iy = seg.y + j;
        const Eigen::Vector2d uv = texel_local_uv(seg, ix, iy);
        const CapsuleRay ray = capsule_ray(frame, seg.w, seg.h, seg.d, uv.x(), uv.y());
        ++st.texels;
        auto hit = own.first_hit(ray.origin, ray.direction);
        if (hit.face >= 0) {
          im.D[pixel(im, ix, iy)] = float(hit.t);
          im.A[pixel(im, ix, iy)] = 1.0f;
          known[size_t(j) * ex + i] = 1;
          ++st.own_hits;
          continue;
        }
        hit = all.first_hit(ray.origin, ray.direction);
        if (hit.face >= 0) {
          im.D[pixel(im, ix, iy)] = float(hit.t);
          known[size_t(j) * ex + i] = 1;
          ++st.other_hits;
        }
      }
    // Rays that met nothing (outside the surface's reach) take their neighbours' values, so the
    // decoder's bilinear lookups near them stay on the surface. Periodic around the axis.
    bool any = false;
    for (char k : known) any |= k;
    if (!any) {
      for (int j = 0; j < ey; ++j)
        for (int i = 0; i < ex; ++i) im.D[pixel(im, seg.x + i, seg.y + j)] = float(seg.radius), ++st.filled;
      continue;
    }
    const bool u_along_x = seg.rotated;  // u runs along atlas x when rotated
    for (bool changed = true; changed;) {
      changed = false;
      std::vector<char> next = known;
      for (int j = 0; j < ey; ++j)
        for (int i = 0; i < ex; ++i) {
          if (known[size_t(j) * ex + i]) continue;
          double sum = 0;
          int n = 0;
          const int di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
          for (int k = 0; k < 4; ++k) {
            int ni = i + di[k], nj = j + dj[k];
            if (u_along_x) ni = (ni + ex) % ex;
            else nj = (nj + ey) % ey;
            if (ni < 0 || nj < 0 || ni >= ex || nj >= ey || !known[size_t(nj) * ex + ni]) continue;
            sum += im.D[pixel(im, seg.x + ni, seg.y + nj)];
            ++n;
          }
          if (n) {
            im.D[pixel(im, seg.x + i, seg.y + j)] = float(sum / n);
            next[size_t(j) * ex + i] = 1;
            ++st.filled;
            changed = true;
          }
        }
      known.swap(next);
    }
  }
  if (options.progress) options.progress("building the base mesh");
  const BaseMesh base = make_base_mesh(mesh, layout, options.base_vertices);
  st.base_faces = int(base.triangles.rows());
  im.layout = layout_to_json(layout);
  im.layout["base_mesh"] = base_mesh_to_json(base);
  if (stats) *stats = st;
  return im;
}

}  // namespace stm
