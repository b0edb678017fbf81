#include "libsdm/encode/encode_sdm.h"

#include "libsdm/encode/base_mesh.h"
#include "libsdm/encode/base_regions.h"
#include "libsdm/encode/texel_targets.h"
#include "libstm/core/parallel.h"
#include "libstm/core/stopwatch.h"
#include "libstm/geometry/capsule_ray.h"
#include "libstm/layout/segments.h"
#include "libstm/geometry/triangle_bvh.h"

#include <cmath>
#include <cstdio>

namespace sdm {
namespace {

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
  return sample_texels(seg, u, v, [&](int ix, int iy) { return double(im.D[texel_index(im, ix, iy)]); });
}

namespace {

// What the texels of every segment are encoded against.
struct EncodeScene {
  Eigen::MatrixX3d V;
  Eigen::MatrixX3i F;
  std::vector<int> face_segment;
  TriangleBvh all;                                // every face of the mesh
  std::vector<std::vector<int>> faces_of;         // per segment, its faces of the mesh
  BaseMesh base;
  BaseRegions regions;  // which input faces each base face's texels may take crossings with
};

EncodeScene encode_scene(const Mesh& mesh, const Layout& layout, const EncodeOptions& options) {
  EncodeScene sc;
  sc.V = vertex_matrix(mesh);
  sc.F = face_matrix(mesh);
  sc.face_segment = assign_faces(mesh, layout);
  sc.all = TriangleBvh(sc.V, sc.F);
  sc.faces_of.resize(layout.segments.size());
  for (size_t f = 0; f < sc.face_segment.size(); ++f) sc.faces_of[sc.face_segment[f]].push_back(int(f));
  report_progress(options.progress, "building the base mesh");
  sc.base = make_base_mesh(mesh, layout, options.base_vertices, options.progress, &sc.all);
  sc.regions = BaseRegions(sc.V, sc.F, sc.base);
  return sc;
}

// The crossing of a ray with the surface nearest a target point of base face `base_face`, among
// those within `reach` of the target's foot on the ray and with faces the base face stands for
// (base_regions.h); face -1 when there is none.
struct Crossing {
  double t = -1, distance = INFINITY;
  int face = -1;
};

Crossing crossing_nearest(const TriangleBvh& all, const BaseRegions& regions, int base_face, const CapsuleRay& ray,
                          const Eigen::Vector3d& target, double foot, double reach) {
  Crossing best;
  double t_min = std::max(0.0, foot - reach);
  for (int n = 0; n < 64; ++n) {
    const auto hit = all.first_hit(ray.origin, ray.direction, t_min, foot + reach);
    if (hit.face < 0) break;
    t_min = hit.t + 1e-9 * (1 + hit.t);
    if (!regions.plausible(hit.face, base_face)) continue;
    const double dist = (ray.origin + hit.t * ray.direction - target).norm();
    if (dist < best.distance) best.distance = dist, best.t = hit.t, best.face = hit.face;
  }
  return best;
}

// The texels of one segment's rectangle.
class SegmentEncoder {
 public:
  SegmentEncoder(const EncodeScene& scene, const Layout& layout, int s, bool fill_unread);
  void encode(SdmImage& im, EncodeStats& st) const;

 private:
  void encode_texel(int ix, int iy, SdmImage& im, EncodeStats& st) const;
  void encode_unread(const CapsuleRay& ray, float& D, float& A, EncodeStats& st) const;

  const EncodeScene& sc_;
  const LayoutSegment& seg_;
  const int s_;
  const bool fill_unread_;  // EncodeOptions::fill_unread
  const TexelTargets targets_;
  TriangleBvh own_;
};

SegmentEncoder::SegmentEncoder(const EncodeScene& scene, const Layout& layout, int s, bool fill_unread)
    : sc_(scene), seg_(layout.segments[s]), s_(s), fill_unread_(fill_unread), targets_(layout, scene.base, scene.base.corner_position, s) {
  if (fill_unread_) own_ = TriangleBvh(sc_.V, sc_.F, sc_.faces_of[s]);  // only encode_unread casts into it
}

// Rows on every core: each texel writes only its own D, A and foot, each row counts into its own
// stats, summed afterwards (the same map and counts on any number of threads).
void SegmentEncoder::encode(SdmImage& im, EncodeStats& st) const {
  int ex, ey;
  extent(seg_, ex, ey);
  std::vector<EncodeStats> row(ey);
  parallel_for(ey, 4, [&](int j) {
    for (int i = 0; i < ex; ++i) encode_texel(seg_.x + i, seg_.y + j, im, row[j]);
  });
  for (const EncodeStats& r : row)
    st.texels += r.texels, st.own_hits += r.own_hits, st.other_hits += r.other_hits, st.filled += r.filled;
}

// Texels no base face reads (texel_targets.h): the first crossing with the segment's own faces,
// else with any, so that image tools show the surface there (a compact map leaves them out).
void SegmentEncoder::encode_unread(const CapsuleRay& ray, float& D, float& A, EncodeStats& st) const {
  auto hit = own_.first_hit(ray.origin, ray.direction);
  if (hit.face >= 0) {
    D = float(hit.t);
    A = 1.0f;
    ++st.own_hits;
    return;
  }
  hit = sc_.all.first_hit(ray.origin, ray.direction);
  D = float(hit.face >= 0 ? hit.t : seg_.radius);
  ++(hit.face >= 0 ? st.other_hits : st.filled);
}

void SegmentEncoder::encode_texel(int ix, int iy, SdmImage& im, EncodeStats& st) const {
  const Eigen::Vector2d uv = texel_local_uv(seg_, ix, iy);
  const CapsuleRay ray = capsule_ray(targets_.frame(), seg_.w, seg_.h, seg_.d, uv.x(), uv.y());
  ++st.texels;
  float& D = im.D[texel_index(im, ix, iy)];
  float& A = im.A[texel_index(im, ix, iy)];
  const auto aim = targets_.target(ray);
  if (!aim) {
    if (fill_unread_) encode_unread(ray, D, A, st);
    else D = NAN;
    return;
  }
  const auto& corner = sc_.base.corner_position[aim->base_face];
  // D = the crossing of the ray with the surface nearest the target, the flat base face's point.
  // The first crossing (or the first with the segment's own faces) is another sheet where the
  // surface is not star-shaped about the capsule (near junctions, in concave bends), and the
  // decoder would put the point there. A ray that grazes a saddle (the crotch between two
  // branches) or leaves without meeting the surface near the face has only far crossings; the
  // target's foot on the ray is then nearer the surface, and it keeps D continuous with the
  // neighbouring texels that do hit. Crossings farther than half the face's longest edge count as
  // far, so only the stretch of the ray within that distance of the foot is searched.
  double longest = 0;
  for (int c = 0; c < 3; ++c) longest = std::max(longest, (corner[c] - corner[(c + 1) % 3]).norm());
  const double reach = 0.5 * longest, foot = aim->foot;
  im.foot[texel_index(im, ix, iy)] = float(foot);
  const Crossing best = crossing_nearest(sc_.all, sc_.regions, aim->base_face, ray, aim->point, foot, reach);
  if (best.face < 0 || best.distance > reach) {
    D = float(std::max(0.0, foot));
    ++st.filled;
  } else {
    D = float(best.t);
    if (sc_.face_segment[best.face] == s_) {
      A = 1.0f;
      ++st.own_hits;
    } else {
      ++st.other_hits;
    }
  }
}

}  // namespace

SdmImage encode_sdm(const Mesh& mesh, const Layout& layout, const EncodeOptions& options, EncodeStats* stats) {
  EncodeStats st;
  SdmImage im;
  im.width = im.height = layout.size;
  im.D.assign(size_t(layout.size) * layout.size, 0.0f);
  im.A.assign(im.D.size(), 0.0f);
  im.foot.assign(im.D.size(), NAN);
  const EncodeScene scene = encode_scene(mesh, layout, options);
  // Progress every 8 segments, with the rate so far and what it leaves for the texels still to do.
  double all_texels = 0;
  for (const LayoutSegment& g : layout.segments) all_texels += double(g.w) * g.h;
  const Stopwatch clock;
  for (size_t s = 0; s < layout.segments.size(); ++s) {
    if (s % 8 == 0) {
      std::string line = "encoding segment " + std::to_string(s + 1) + "/" + std::to_string(layout.segments.size());
      const double t = clock.seconds();
      if (st.texels > 0 && t > 0.5) {
        char rate[96];
        std::snprintf(rate, sizeof rate, " (%.2f M texels/s, about %.0f s left)", st.texels / t / 1e6,
                      std::ceil((all_texels - double(st.texels)) * t / double(st.texels)));
        line += rate;
      }
      report_progress(options.progress, line);
    }
    SegmentEncoder(scene, layout, int(s), options.fill_unread).encode(im, st);
  }
  st.base_faces = int(scene.base.triangles.rows());
  im.layout = layout_to_json(layout);
  im.layout["base_mesh"] = base_mesh_to_json(scene.base);
  if (stats) *stats = st;
  return im;
}

}  // namespace sdm
