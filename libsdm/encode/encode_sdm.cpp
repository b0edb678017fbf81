#include "libsdm/encode/encode_sdm.h"

#include "libsdm/encode/base_mesh.h"
#include "libsdm/encode/base_regions.h"
#include "libsdm/map/texel_targets.h"
#include "libsdm/decode/decode_sdm.h"
#include "libstm/core/parallel.h"
#include "libstm/core/stopwatch.h"
#include "libstm/geometry/capsule_ray.h"
#include "libstm/layout/assign_layout_faces.h"
#include "libstm/layout/layout_json.h"
#include "libstm/layout/segments.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/mesh/mesh_geometry.h"

#include <cmath>
#include <cstdio>
#include <optional>

namespace sdm {
namespace {

// The rectangle's extent in atlas texels: w along the axis, h around it (layout.h conventions).
void extent(const LayoutSegment& s, int& ex, int& ey) {
  ex = s.rotated ? s.h : s.w;
  ey = s.rotated ? s.w : s.h;
}

}  // namespace

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

// The scene, and the source the base mesh is decimated from (built beside the faces' segments: on a
// large mesh both take about a second, and the source's remesh runs on one core).
EncodeScene encode_scene(const Mesh& mesh, const Layout& layout, int base_vertices, std::optional<BaseMeshSource>& source) {
  EncodeScene sc;
  sc.V = vertex_matrix(mesh);
  sc.F = face_matrix(mesh);
  sc.all = TriangleBvh(sc.V, sc.F);
  run_concurrently([&] { source.emplace(mesh, layout, base_vertices, &sc.all); },
                   [&] { sc.face_segment = assign_faces(mesh, layout); });
  sc.faces_of.resize(layout.segments.size());
  for (size_t f = 0; f < sc.face_segment.size(); ++f) sc.faces_of[sc.face_segment[f]].push_back(int(f));
  return sc;
}

void set_base(EncodeScene& sc, BaseMesh base) {
  sc.base = std::move(base);
  sc.regions = BaseRegions(sc.V, sc.F, sc.base);
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

namespace {

// Every texel of every segment against the scene's base mesh.
SdmImage encode_texels(const EncodeScene& scene, const Layout& layout, const EncodeOptions& options, EncodeStats& st) {
  st = EncodeStats();
  SdmImage im;
  im.width = im.height = layout.size;
  im.D.assign(size_t(layout.size) * layout.size, 0.0f);
  im.A.assign(im.D.size(), 0.0f);
  im.foot.assign(im.D.size(), NAN);
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
  return im;
}

// The level the map is checked at: the decoder's default, whose points lie between those of level 2
// (a check at level 2 missed the CAD parts' worst faces).
constexpr int kCheckLevel = 3;
// Rounds of flat faces chosen and the map checked again (each decodes the map once more).
constexpr int kFlatPasses = 3;
// A face whose decoded points are close enough but whose decoded edges are too long goes flat only
// when its flat triangle is this close (in limits): a plate. On a curved surface its flat points
// would lie off the surface where the decoded ones do not (a 449k-vertex bunny's map with such faces
// flat at the limit: RMS 0.0070 -> 0.0141 %).
constexpr double kFlatEnough = 0.1;
// How far beyond the limit distances are measured (decoded_errors).
constexpr double kCheckCap = 8;
// A decoded triangle whose distance bound through its corners exceeds the limit is measured at its
// centroid and, when longer than 3 kCheckSpacing limits, at a barycentric grid with steps of about
// kCheckSpacing limits along its longest side (at most kCheckGrid steps).
constexpr double kCheckSpacing = 4;
constexpr int kCheckGrid = 12;

// Per base face, the largest distance from the input surface of its points decoded at kCheckLevel
// and of the centroids of its decoded triangles (a CAD part's base face across a sharp edge decodes
// to points on both sides, and its triangles cut the edge: rotor, 2.7 % of the diagonal with every
// point on the surface).
// Distances are looked for within `limit` first and then within `cap` (farther ones count as cap):
// small balls prune most of the tree, and the check is about the few points beyond the limit.
// A triangle's centroid (and, when large, a grid of its points: kCheckSpacing) is measured only when
// its distance bound through the corners (a corner's distance plus the way to it) exceeds the
// limit: on dense meshes few are.
struct FaceErrors {
  std::vector<double> distance;  // per base face, the largest distance of its points from the input
  std::vector<char> long_edge;   // per base face, whether a decoded edge is longer than the input's longest
};
FaceErrors decoded_errors(const SdmImage& im, const TriangleBvh& input, double limit, double cap, double longest, int base_faces,
                          const std::vector<int>& faces = {}) {
  DecodeOptions o;
  o.level = kCheckLevel;
  const DecodedSurface out = decode_surface(im, o, faces);
  const auto& P = out.points;
  const auto& T = out.triangles;
  const int nv = int(P.size()), nt = int(T.rows());
  auto distance = [&](const Eigen::Vector3d& q) {
    TriangleBvh::Closest c = input.closest_point(q, limit);
    if (c.face < 0) c = input.closest_point(q, cap);
    return c.face < 0 ? cap : c.distance;
  };
  std::vector<double> d(size_t(nv + nt));
  parallel_for(nv, 4096, [&](int i) { d[size_t(i)] = distance(P[size_t(i)]); });
  parallel_for(nt, 4096, [&](int t) {
    const Eigen::Vector3d* q[3] = {&P[size_t(T(t, 0))], &P[size_t(T(t, 1))], &P[size_t(T(t, 2))]};
    const Eigen::Vector3d c = (*q[0] + *q[1] + *q[2]) / 3;
    double bound = INFINITY;
    for (int k = 0; k < 3; ++k) bound = std::min(bound, d[size_t(T(t, k))] + (c - *q[k]).norm());
    if (bound <= limit) {
      d[size_t(nv + t)] = bound;
      return;
    }
    // The centroid, and on a large triangle a grid of points: a CAD part's decoded triangle across a
    // concave edge had its corners and centroid on the surface and its middle 1.8 % of the diagonal off.
    double longest_side = 0;
    for (int k = 0; k < 3; ++k) longest_side = std::max(longest_side, (*q[k] - *q[(k + 1) % 3]).norm());
    const int m = 3 * std::clamp(int(std::ceil(longest_side / (kCheckSpacing * limit) / 3)), 1, kCheckGrid / 3);
    double worst = distance(c);
    for (int i = 0; i <= m && m > 3; ++i)
      for (int j = 0; i + j <= m; ++j)
        if (i != m && j != m && i + j != 0)
          worst = std::max(worst, distance((double(i) * *q[0] + double(j) * *q[1] + double(m - i - j) * *q[2]) / double(m)));
    d[size_t(nv + t)] = worst;
  });
  FaceErrors err{std::vector<double>(size_t(base_faces), 0.0), std::vector<char>(size_t(base_faces), 0)};
  for (int i = 0; i < nv + nt; ++i) {
    double& e = err.distance[size_t(i < nv ? out.point_face[size_t(i)] : out.triangle_face[size_t(i - nv)])];
    e = std::max(e, d[size_t(i)]);
  }
  // The bound: no decoded edge longer than the input's longest.
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
      if ((P[size_t(T(t, k))] - P[size_t(T(t, (k + 1) % 3))]).norm() > longest) err.long_edge[size_t(out.triangle_face[size_t(t)])] = 1;
  return err;
}

// For the base faces `faces`, the largest distance from the input surface of the points of their
// flat triangles at barycentric steps of 1 / 2^(kCheckLevel + 1) (the decoded points and between
// them), within `cap` as for decoded_errors; 0 for the other faces.
std::vector<double> flat_errors(const BaseMesh& base, const TriangleBvh& input, double cap, const std::vector<int>& faces) {
  const int n = 2 << kCheckLevel;
  std::vector<double> err(base.corner_position.size(), 0.0);
  parallel_for(int(faces.size()), 16, [&](int k) {
    const int f = faces[size_t(k)];
    const auto& c = base.corner_position[size_t(f)];
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Eigen::Vector3d p = (double(i) * c[0] + double(j) * c[1] + double(n - i - j) * c[2]) / double(n);
        const TriangleBvh::Closest q = input.closest_point(p, cap);
        err[size_t(f)] = std::max(err[size_t(f)], q.face < 0 ? cap : q.distance);
      }
  });
  return err;
}

// What the encoder checks its map against (fractions of the diagonal, in model units).
struct MapCheck {
  double limit = 0;    // flat_above: faces beyond it are placed flat when that is closer
  double refine = 0;   // refine_above: faces still beyond it make the base mesh finer there
  double cap = 0;      // distances are looked for up to here
  double longest = 0;  // the input's longest edge: no decoded edge may be longer
};

// Chooses the base faces the decoder places flat (scene.base.flat_faces, im's header) and returns
// every face's decoded errors with them. A face decoded beyond the limit goes flat when its flat
// triangle lies closer than its decoded points; a face whose only fault is a decoded edge longer
// than the input's longest, when its flat triangle lies within kFlatEnough limits (flat faces' edges
// are at most 7/8 of the input's longest at level 3: kMaxBaseEdge). A flat face's edges' points are
// flat too (decode_sdm), which can move a neighbour's triangles off the surface in turn, so the
// faces around new flat ones are decoded again, up to kFlatPasses times.
FaceErrors place_flat_faces(SdmImage& im, EncodeScene& scene, const MapCheck& mc) {
  BaseMesh& base = scene.base;
  const int nf = int(base.triangles.rows());
  FaceErrors err = decoded_errors(im, scene.all, mc.limit, mc.cap, mc.longest, nf);
  std::vector<double> flat(size_t(nf), NAN);  // measured when first needed
  std::vector<char> is_flat(size_t(nf), 0);
  auto bad = [&](int f) { return !is_flat[size_t(f)] && (err.distance[size_t(f)] > mc.limit || err.long_edge[size_t(f)]); };
  for (int pass = 0; pass < kFlatPasses; ++pass) {
    std::vector<int> over;
    for (int f = 0; f < nf; ++f)
      if (bad(f) && std::isnan(flat[size_t(f)])) over.push_back(f);
    const std::vector<double> measured = flat_errors(base, scene.all, mc.cap, over);
    for (int f : over) flat[size_t(f)] = measured[size_t(f)];
    std::vector<char> changed_corner(size_t(base.triangles.maxCoeff() + 1), 0);
    bool more = false;
    for (int f = 0; f < nf; ++f)
      if (bad(f) && (err.distance[size_t(f)] > mc.limit ? flat[size_t(f)] < err.distance[size_t(f)] : flat[size_t(f)] <= kFlatEnough * mc.limit)) {
        is_flat[size_t(f)] = 1, more = true;
        for (int c = 0; c < 3; ++c) changed_corner[size_t(base.triangles(f, c))] = 1;
      }
    if (!more) break;
    base.flat_faces.clear();
    for (int f = 0; f < nf; ++f)
      if (is_flat[size_t(f)]) base.flat_faces.push_back(f);
    im.layout["base_mesh"] = base_mesh_to_json(base);
    std::vector<int> around;
    for (int f = 0; f < nf; ++f)
      if (changed_corner[size_t(base.triangles(f, 0))] || changed_corner[size_t(base.triangles(f, 1))] ||
          changed_corner[size_t(base.triangles(f, 2))])
        around.push_back(f);
    const FaceErrors again = decoded_errors(im, scene.all, mc.limit, mc.cap, mc.longest, nf, around);
    for (int f : around) err.distance[size_t(f)] = again.distance[size_t(f)], err.long_edge[size_t(f)] = again.long_edge[size_t(f)];
  }
  return err;
}

// Marks in `keep` the source's vertices nearest the faces `unresolved` and the faces around them
// (sharing a corner); returns how many are marked in all.
long keep_around(const std::vector<int>& unresolved, const BaseMeshSource& source, const BaseMesh& base, std::vector<char>& keep) {
  const Eigen::MatrixX3d points = source.points();
  const BaseRegions owners(points, Eigen::MatrixX3i(), base);
  const Eigen::MatrixX3i& T = base.triangles;
  std::vector<char> corner(size_t(T.maxCoeff() + 1), 0), worse(size_t(T.rows()), 0);
  for (int f : unresolved)
    for (int c = 0; c < 3; ++c) corner[size_t(T(f, c))] = 1;
  for (Eigen::Index f = 0; f < T.rows(); ++f) worse[size_t(f)] = corner[size_t(T(f, 0))] | corner[size_t(T(f, 1))] | corner[size_t(T(f, 2))];
  keep.resize(size_t(points.rows()), 0);
  long kept = 0;
  for (size_t v = 0; v < keep.size(); ++v) kept += (keep[v] |= worse[size_t(owners.owner(int(v)))]);
  return kept;
}

}  // namespace

// A map texel holds one depth per ray. Where a base face's rays graze the surface (a CAD plate seen
// edge-on by every capsule near it), neighbouring texels hold far apart depths and the bilinear
// lookup puts points off the surface (anchor_dense, rotor: Hausdorff 1.9 and 2.7 % of the diagonal);
// where a base face spans a sharp edge, its decoded triangles cut it even with every point on the
// surface. So the map is checked at level 3: faces decoded farther than flat_above from the input
// are placed flat when their flat triangle is closer (place_flat_faces), and where faces stay
// beyond refine_above, the source's vertices nearest them are kept and the base mesh is decimated
// again (its faces there are then the source's own, on the surface).
SdmImage encode_sdm(const Mesh& mesh, const Layout& layout, const EncodeOptions& options, EncodeStats* stats) {
  report_progress(options.progress, "building the base mesh");
  std::optional<BaseMeshSource> base_source;
  EncodeScene scene = encode_scene(mesh, layout, options.base_vertices, base_source);
  const BaseMeshSource& source = *base_source;
  const double diag = bounding_box_diagonal(mesh);
  MapCheck mc;
  mc.limit = options.flat_above * diag;
  mc.refine = std::max(mc.limit, options.refine_above * diag);
  mc.cap = kCheckCap * mc.limit;
  mc.longest = longest_edge(mesh);
  std::vector<char> keep;
  EncodeStats st;
  for (int round = 0;; ++round) {
    set_base(scene, source.decimate(keep, options.progress));
    SdmImage im = encode_texels(scene, layout, options, st);
    st.decimations = round + 1;
    st.kept = std::count(keep.begin(), keep.end(), char(1));
    std::vector<int> unresolved;
    double worst = 0;
    if (mc.limit > 0) {
      const FaceErrors err = place_flat_faces(im, scene, mc);
      // Long edges alone do not make the base mesh finer: on a fine input (449k vertices) the
      // decoded edges of curved faces reach just over the input's longest everywhere, and two more
      // decimations (16.8 s instead of 7.2 s) still left 452 such faces.
      for (int f = 0; f < int(err.distance.size()); ++f)
        if (err.distance[size_t(f)] > mc.refine) unresolved.push_back(f), worst = std::max(worst, err.distance[size_t(f)]);
    }
    if (unresolved.empty() || round == options.refine_rounds) {
      st.flat_faces = int(scene.base.flat_faces.size());
      if (stats) *stats = st;
      return im;
    }
    const long kept = keep_around(unresolved, source, scene.base, keep);
    char line[200];
    std::snprintf(line, sizeof line, "base mesh: %zu faces decode off the surface by up to %.2f %% of the diagonal; keeping %ld vertices of the input there",
                  unresolved.size(), 100 * worst / diag, kept);
    report_progress(options.progress, line);
  }
}

}  // namespace sdm
