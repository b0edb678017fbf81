#include "libsdm/encode/encode_sdm.h"

#include "libsdm/encode/base_mesh.h"
#include "libstm/geometry/capsule_ray.h"
#include "libstm/geometry/differential_geometry.h"
#include "libstm/layout/segments.h"
#include "libstm/geometry/triangle_bvh.h"

#include <cmath>

namespace sdm {
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
  const TriangleBvh all(V, F);
  std::vector<std::vector<int>> faces_of(layout.segments.size());
  for (size_t f = 0; f < face_segment.size(); ++f) faces_of[face_segment[f]].push_back(int(f));
  if (options.progress) options.progress("building the base mesh");
  const BaseMesh base = make_base_mesh(mesh, layout, options.base_vertices);
  std::vector<std::vector<int>> base_faces_of(layout.segments.size());
  for (int f = 0; f < base.triangles.rows(); ++f) base_faces_of[base.face_segment[f]].push_back(f);

  for (size_t s = 0; s < layout.segments.size(); ++s) {
    const LayoutSegment& seg = layout.segments[s];
    if (options.progress && s % 8 == 0)
      options.progress("encoding segment " + std::to_string(s + 1) + "/" + std::to_string(layout.segments.size()));
    const CapsuleFrame frame = capsule_frame(layout, int(s));
    // The segment's base faces on the reference capsule, exactly as the decoder builds them: the
    // decoder places a point of a base face on the ray through that point of its reference
    // triangle, so a texel's ray crossing a reference triangle is the texel that face will read.
    const std::vector<int>& own_base = base_faces_of[s];
    Eigen::MatrixX3d R(3 * own_base.size(), 3);
    Eigen::MatrixX3i RF(own_base.size(), 3);
    for (size_t k = 0; k < own_base.size(); ++k)
      for (int c = 0; c < 3; ++c) {
        const auto& uv = base.corner_uv[own_base[k]][c];
        const CapsuleRay ray = capsule_ray(frame, seg.w, seg.h, seg.d, uv.x(), uv.y());
        R.row(3 * k + c) = (ray.origin + seg.radius * ray.direction).transpose();
        RF(Eigen::Index(k), c) = int(3 * k + c);
      }
    const TriangleBvh reference(R, RF);
    const TriangleBvh own(V, F, faces_of[s]);
    // Texel size on the reference capsule (around the axis, and along it on the cylinder).
    const double texel = std::max(2 * M_PI * seg.radius / seg.h, seg.length / std::max(1.0, seg.w - 2 * seg.d));
    int ex, ey;
    extent(seg, ex, ey);
    for (int j = 0; j < ey; ++j)
      for (int i = 0; i < ex; ++i) {
        const int ix = seg.x + i, iy = seg.y + j;
        const Eigen::Vector2d uv = texel_local_uv(seg, ix, iy);
        const CapsuleRay ray = capsule_ray(frame, seg.w, seg.h, seg.d, uv.x(), uv.y());
        ++st.texels;
        float& D = im.D[pixel(im, ix, iy)];
        // Texels no base face reads (the decoder's bilinear lookups reach one texel beyond a
        // face; texels more than 4 from every reference triangle, measured on the capsule where
        // the map's stretch varies, are out of reach): the first crossing with the segment's own
        // faces, else with any.
        auto unread = [&]() {
          auto hit = own.first_hit(ray.origin, ray.direction);
          if (hit.face >= 0) {
            D = float(hit.t);
            im.A[pixel(im, ix, iy)] = 1.0f;
            ++st.own_hits;
            return;
          }
          hit = all.first_hit(ray.origin, ray.direction);
          D = float(hit.face >= 0 ? hit.t : seg.radius);
          ++(hit.face >= 0 ? st.other_hits : st.filled);
        };
        if (own_base.empty()) {
          unread();
          continue;
        }
        // Where the decoder's flat base triangle puts this texel (target), from the texel's
        // crossing with a reference triangle, or, for texels between faces and around the
        // segment's region, from the nearest reference triangle (what bilinear lookups near the
        // region's border read).
        int k = -1;
        Eigen::Vector3d bary;
        const auto cross = reference.first_hit(ray.origin, ray.direction);
        if (cross.face >= 0) {
          k = cross.face;
          bary = {1 - cross.u - cross.v, cross.u, cross.v};
        } else {
          const auto near = reference.closest_point(ray.origin + seg.radius * ray.direction);
          if (near.distance > 4 * texel) {
            unread();
            continue;
          }
          k = near.face;
          bary = barycentric(near.point, R.row(3 * k), R.row(3 * k + 1), R.row(3 * k + 2));
        }
        const auto& corner = base.corner_position[own_base[k]];
        const Eigen::Vector3d target = bary[0] * corner[0] + bary[1] * corner[1] + bary[2] * corner[2];
        // D = the crossing of the ray with the surface nearest that target. The first crossing
        // (or the first with the segment's own faces) is another sheet where the surface is not
        // star-shaped about the capsule (near junctions, in concave bends), and the decoder would
        // put the point there. A ray that grazes a saddle (the crotch between two branches) or
        // leaves without meeting the surface near the face has only far crossings; the target's
        // foot on the ray is then nearer the surface, and it keeps D continuous with the
        // neighbouring texels that do hit. Crossings farther than half the face's longest edge
        // count as far, so only the stretch of the ray within that distance of the foot is searched.
        double longest = 0;
        for (int c = 0; c < 3; ++c) longest = std::max(longest, (corner[c] - corner[(c + 1) % 3]).norm());
        const double reach = 0.5 * longest, foot = (target - ray.origin).dot(ray.direction);
        double best_t = -1, best = INFINITY;
        int best_face = -1;
        double t_min = std::max(0.0, foot - reach);
        for (int n = 0; n < 64; ++n) {
          const auto hit = all.first_hit(ray.origin, ray.direction, t_min, foot + reach);
          if (hit.face < 0) break;
          const double dist = (ray.origin + hit.t * ray.direction - target).norm();
          if (dist < best) best = dist, best_t = hit.t, best_face = hit.face;
          t_min = hit.t + 1e-9 * (1 + hit.t);
        }
        if (best_face < 0 || best > reach) {
          D = float(std::max(0.0, foot));
          ++st.filled;
        } else {
          D = float(best_t);
          if (face_segment[best_face] == int(s)) {
            im.A[pixel(im, ix, iy)] = 1.0f;
            ++st.own_hits;
          } else {
            ++st.other_hits;
          }
        }
      }
  }
  st.base_faces = int(base.triangles.rows());
  im.layout = layout_to_json(layout);
  im.layout["base_mesh"] = base_mesh_to_json(base);
  if (stats) *stats = st;
  return im;
}

}  // namespace sdm
