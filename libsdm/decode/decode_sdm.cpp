#include "libsdm/decode/decode_sdm.h"

#include "libsdm/map/base_mesh_record.h"
#include "libsdm/map/texels.h"
#include "libsdm/decode/tessellate_mesh.h"
#include "libsdm/pose/deform_decoded.h"
#include "libsdm/map/texel_targets.h"
#include "libstm/geometry/capsule_ray.h"
#include "libstm/geometry/vertex_normals.h"
#include "libstm/core/errors.h"
#include "libstm/core/parallel.h"
#include "libstm/layout/layout.h"
#include "libstm/layout/layout_json.h"
#include "libstm/mesh/add_faces.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <memory>
#include <stdexcept>

namespace sdm {
namespace {

// The level of each segment: options.level, or its --lod-segment override. Throws InputError for
// a level outside 0..8 or an unknown segment.
std::vector<int> segment_levels(int segments, const DecodeOptions& options) {
  auto check_level = [](int level) {
    if (level < 0 || level > 8) throw InputError("level of detail " + std::to_string(level) + " is out of range 0..8");
  };
  check_level(options.level);
  std::vector<int> level(size_t(segments), options.level);
  for (const auto& [s, l] : options.segment_level) {
    if (s < 0 || s >= segments)
      throw InputError("--lod-segment names segment " + std::to_string(s) + " but the SDM has " + std::to_string(segments) +
                       " segments (0.." + std::to_string(segments - 1) + ")");
    check_level(l);
    level[s] = l;
  }
  return level;
}

// A decoded point before it is placed: its segment, its ray and (u, v), and its flat base point.
struct PointRay {
  int segment = 0;
  CapsuleRay ray;
  double u = 0, v = 0;
  Eigen::Vector3d flat;
};

// The texels the decoded points' lookups read, each with its displacement and the base face it was
// encoded for (texel_targets.h; computed from the decoded corners, in parallel). A quantised map
// stores a residual: its displacement is that plus the encoder's prediction, the foot of its base
// face's flat point on its ray.
class TexelReads {
 public:
  TexelReads(const SdmImage& image, const Layout& layout, const BaseMesh& base, const std::vector<std::array<Eigen::Vector3d, 3>>& corners)
      : image_(image), layout_(layout), base_(base), corners_(corners), targets_(layout.segments.size()) {}

  // A float map's point whose four depths lie within a quarter of its face's reach
  // (reach[point_face[i]]) of each other reads texels of one sheet and takes them as they are; the
  // others have the base face of each texel computed (a
  // search of the segment's reference triangles per texel: the 30k-vertex bunny's level-3 decode
  // 0.23 -> 0.36 s when done for every texel). A quantised map's texels need their base face's
  // prediction for their depth anyway, and all its points are checked (checking only the spread
  // ones there: rotor RMS 0.32 -> 0.36 %).
  void prepare(const std::vector<PointRay>& points, const std::vector<int>& point_face, const std::vector<double>& reach) {
    face_.assign(image_.D.size(), -1);
    checked_.assign(points.size(), 1);
    if (image_.residual) {
      value_.assign(image_.D.size(), NAN);
      compute_texels(points, [](size_t) { return true; });
      return;
    }
    parallel_for(int(points.size()), 4096, [&](int i) {
      const PointRay& p = points[size_t(i)];
      double lo = INFINITY, hi = -INFINITY;
      sample_texels(layout_.segments[p.segment], p.u, p.v, [&](int ix, int iy) {
        const double d = value(ix, iy);
        if (!std::isnan(d)) lo = std::min(lo, d), hi = std::max(hi, d);
        return 0.0;
      });
      checked_[size_t(i)] = hi - lo > 0.25 * reach[size_t(point_face[size_t(i)])];
    });
    compute_texels(points, [&](size_t i) { return checked_[i] != 0; });
  }

  // Whether point i's texels were given their base faces (prepare).
  bool checked(size_t i) const { return checked_[i]; }

  // Texel (ix, iy) (prepared): its displacement (NaN when left out) and its base face (-1: none).
  double value(int ix, int iy) const {
    const size_t i = texel_index(image_, ix, iy);
    return double(image_.residual ? value_[i] : image_.D[i]);
  }
  int face(int ix, int iy) const { return face_[texel_index(image_, ix, iy)]; }

 private:
  // The texels read by the points `which` selects, each computed once.
  template <class Which>
  void compute_texels(const std::vector<PointRay>& points, const Which& which) {
    std::vector<char> needed(image_.D.size(), 0);
    struct Texel {
      int segment, ix, iy;
    };
    std::vector<Texel> todo;
    for (size_t i = 0; i < points.size(); ++i) {
      if (!which(i)) continue;
      const PointRay& p = points[i];
      if (!targets_[p.segment]) targets_[p.segment] = std::make_unique<TexelTargets>(layout_, base_, corners_, p.segment);
      sample_texels(layout_.segments[p.segment], p.u, p.v, [&](int ix, int iy) {
        char& seen = needed[texel_index(image_, ix, iy)];
        if (!seen) seen = 1, todo.push_back({p.segment, ix, iy});
        return 0.0;
      });
    }
    parallel_for(int(todo.size()), 1024, [&](int k) { compute(todo[size_t(k)].segment, todo[size_t(k)].ix, todo[size_t(k)].iy); });
  }

  void compute(int s, int ix, int iy) {
    const size_t i = texel_index(image_, ix, iy);
    const LayoutSegment& seg = layout_.segments[s];
    const Eigen::Vector2d uv = texel_local_uv(seg, ix, iy);
    const auto aim = targets_[s]->target(capsule_ray(targets_[s]->frame(), seg.w, seg.h, seg.d, uv.x(), uv.y()));
    face_[i] = aim ? aim->base_face : -1;
    if (image_.residual && aim && !std::isnan(image_.D[i])) value_[i] = float(aim->foot + image_.D[i]);
  }

  const SdmImage& image_;
  const Layout& layout_;
  const BaseMesh& base_;
  const std::vector<std::array<Eigen::Vector3d, 3>>& corners_;
  std::vector<std::unique_ptr<TexelTargets>> targets_;
  std::vector<float> value_;
  std::vector<int> face_;
  std::vector<char> checked_;
};

// The bilinear lookup of a point of base face f over the texels encoded for f or for a face that
// shares a corner with it (the others, and texels no face reads, skipped, the weights renormalised;
// NaN when none is left).
// A texel read near a face's border can be encoded for another base face whose reference triangle
// overlaps this face's on the capsule: another sheet along the ray. On FAUST 085 such a texel,
// encoded for the hanging hand, put a point of the hip 6 cm off (Hausdorff 2.75 %, now 0.55 %; the
// TOSCA man 2.46 -> 0.62 %, the two-tunnels bar 2.38 -> 0.17 %). Filtering by depth instead (texels
// within the face's reach of its flat point's foot) also removed the spikes but raised bunny00's
// RMS from 0.0115 to 0.0156 %, dropping right texels where rays graze the surface; by face: 0.0111 %.
double sample_own_texels(const BaseMesh& base, const LayoutSegment& seg, const TexelReads& reads, size_t point, int f, double u,
                         double v) {
  if (!reads.checked(point)) return sample_texels(seg, u, v, [&](int ix, int iy) { return reads.value(ix, iy); });
  return sample_texels(seg, u, v, [&](int ix, int iy) {
    const int g = reads.face(ix, iy);
    return g >= 0 && faces_share_corner(base.triangles, f, g) ? reads.value(ix, iy) : NAN;
  });
}

// Corners on a reference capsule of the segment's radius (their rays, at their stored (u, v)).
// Points inside a face take the ray through their flat point instead, through capsule_uv, which
// handles the phi = 0 seam and the poles, where (u, v) themselves jump.
std::vector<std::array<Eigen::Vector3d, 3>> reference_corners(const BaseMesh& base, const Layout& layout,
                                                              const std::vector<CapsuleFrame>& frames) {
  std::vector<std::array<Eigen::Vector3d, 3>> reference(base.triangles.rows());
  for (int f = 0; f < base.triangles.rows(); ++f) {
    const LayoutSegment& seg = layout.segments[base.face_segment[f]];
    for (int c = 0; c < 3; ++c) {
      const auto& uv = base.corner_uv[f][c];
      const CapsuleRay ray = capsule_ray(frames[base.face_segment[f]], seg.w, seg.h, seg.d, uv.x(), uv.y());
      reference[f][c] = ray.origin + seg.radius * ray.direction;
    }
  }
  return reference;
}

// Per base face, half its longest decoded edge: how far its points may lie from its flat triangle.
std::vector<double> face_reach(const std::vector<std::array<Eigen::Vector3d, 3>>& corner) {
  std::vector<double> reach(corner.size());
  for (size_t f = 0; f < corner.size(); ++f) {
    double longest = 0;
    for (int c = 0; c < 3; ++c) longest = std::max(longest, (corner[f][c] - corner[f][(c + 1) % 3]).norm());
    reach[f] = 0.5 * longest;
  }
  return reach;
}

std::vector<Eigen::Vector3d> flat_points_of(const std::vector<PointRay>& at) {
  std::vector<Eigen::Vector3d> flat(at.size());
  for (size_t i = 0; i < at.size(); ++i) flat[i] = at[i].flat;
  return flat;
}

// The base mesh's vertex normals: the area-weighted normals of the decoded base faces around each
// corner, so that a normal interpolated over a face is continuous across its edges and corners.
std::vector<Eigen::Vector3d> base_vertex_normals(const BaseMesh& base, const std::vector<std::array<Eigen::Vector3d, 3>>& corner) {
  const int nv = base.triangles.rows() ? base.triangles.maxCoeff() + 1 : 0;
  std::vector<Eigen::Vector3d> normal =
      vertex_area_vectors(base.triangles, size_t(nv), [&](int f, int k) -> const Eigen::Vector3d& { return corner[size_t(f)][size_t(k)]; });
  for (Eigen::Vector3d& n : normal) n.normalize();
  return normal;
}

// Where the line from point a's flat point along the interpolated base normal n meets the surface
// the map holds for a's segment (DESIGN 4.8): below(x, b) sets b to how far the map's surface lies
// beyond x along the segment's ray through x (false where the map holds nothing there). The ray
// point on_ray (already on that surface) starts a secant search; it is kept where the normal runs
// nearly across the rays (|n . ray| < 0.3), where the search leaves the face's reach r, or does not
// settle within 1e-3 r. The rays of two segments differ at a base edge between them, and the rays of
// one segment fan out from its axis: neighbouring points moved along them land on the surface in the
// wrong order where the displacement is large against the decoded edges, and their triangles fold
// (Spot at level 2: 254 crossing face pairs by rays, 47 by normals; at level 1 20 and 0). The
// normals are continuous over the base mesh, so neighbouring points move alike.
template <class Below>
Eigen::Vector3d along_normal(const PointRay& a, const Eigen::Vector3d& n, const Eigen::Vector3d& on_ray, double r, const Below& below) {
  if (!(std::abs(n.dot(a.ray.direction)) > 0.3)) return on_ray;
  double l0 = 0, g0 = 0, l1 = (on_ray - a.flat).dot(n), g1 = 0;
  if (!below(a.flat, g0) || !below(a.flat + l1 * n, g1)) return on_ray;
  for (int it = 0; it < 12 && g1 != g0; ++it) {
    const double l2 = l1 - g1 * (l1 - l0) / (g1 - g0);
    if (!(std::abs(l2) < r)) return on_ray;
    l0 = l1, g0 = g1, l1 = l2;
    if (!below(a.flat + l1 * n, g1)) return on_ray;
    if (std::abs(l1 - l0) < 1e-7 * r) break;
  }
  return std::abs(g1) < 1e-3 * r ? Eigen::Vector3d(a.flat + l1 * n) : on_ray;
}

// Which points lie on the flat triangles of the base mesh's flat faces (empty when it has none): the
// points of those faces and the points on their edges, whatever face the tessellation evaluates an
// edge's points in, so that both faces along the edge have it where the flat face needs it.
std::vector<char> flat_points(const BaseMesh& base, const Tessellation& tess) {
  if (base.flat_faces.empty()) return {};
  std::vector<char> face(size_t(base.triangles.rows()), 0);
  std::vector<std::pair<int, int>> edges;
  for (int f : base.flat_faces) {
    face[size_t(f)] = 1;
    for (int c = 0; c < 3; ++c) edges.push_back(std::minmax(base.triangles(f, c), base.triangles(f, (c + 1) % 3)));
  }
  std::sort(edges.begin(), edges.end());
  std::vector<char> flat(tess.point_face.size(), 0);
  for (size_t i = 0; i < flat.size(); ++i) {
    const int f = tess.point_face[i];
    if (face[size_t(f)]) {
      flat[i] = 1;
      continue;
    }
    // On an edge of f: the barycentric coordinate of the corner opposite it is 0.
    for (int k = 0; k < 3; ++k)
      if (std::abs(tess.point_bary[i][k]) < 1e-9) {
        const std::pair<int, int> e = std::minmax(base.triangles(f, (k + 1) % 3), base.triangles(f, (k + 2) % 3));
        if (std::binary_search(edges.begin(), edges.end(), e)) flat[i] = 1;
      }
  }
  return flat;
}

}  // namespace

DecodeEstimate estimate_decode(const SdmImage& image, const DecodeOptions& options) {
  const Layout layout = layout_from_json(image.layout);
  if (!image.layout.contains("base_mesh"))
    throw InputError("the SDM header has no base mesh: it was written by an older 'sdm encode'; encode it again");
  const BaseMesh base = base_mesh_from_json(image.layout.at("base_mesh"), int(layout.segments.size()));
  const std::vector<int> level = segment_levels(int(layout.segments.size()), options);
  DecodeEstimate e;
  for (int s : base.face_segment) e.triangles += std::pow(4.0, level[s]);
  // 450 bytes a decoded triangle (measured), and 9 a texel of the atlas: the decoder's texel depth,
  // base face and seen flag (TexelReads).
  e.bytes = 450 * e.triangles + 9.0 * double(image.width) * double(image.height);
  return e;
}

namespace {

// The tessellation of the base faces `faces` (every face when empty), each at its segment's level;
// point_face and triangle_face hold base mesh faces.
Tessellation tessellate_faces(const BaseMesh& base, const std::vector<int>& level, const std::vector<int>& faces) {
  Tessellation tess;
  if (faces.empty()) {
    std::vector<int> rate(base.triangles.rows());
    for (int f = 0; f < base.triangles.rows(); ++f) rate[f] = 1 << level[base.face_segment[f]];
    tess = tessellate_mesh(base.triangles, rate);
  } else {
    // The chosen faces alone, their indices mapped back to the base mesh's.
    Eigen::MatrixX3i some(Eigen::Index(faces.size()), 3);
    std::vector<int> rate(faces.size());
    for (size_t k = 0; k < faces.size(); ++k) {
      if (faces[k] < 0 || faces[k] >= base.triangles.rows()) throw std::invalid_argument("decode_surface: no such base face");
      some.row(Eigen::Index(k)) = base.triangles.row(faces[k]);
      rate[k] = 1 << level[base.face_segment[size_t(faces[k])]];
    }
    tess = tessellate_mesh(some, rate);
    for (int& f : tess.point_face) f = faces[size_t(f)];
    for (int& f : tess.triangle_face) f = faces[size_t(f)];
  }
  return tess;
}

// decode_surface, with `beside` (when given) run on a second thread once the tessellation is known,
// while the points are placed: decode_sdm builds the output's connectivity there.
DecodedSurface decode_surface_beside(const SdmImage& image, const DecodeOptions& options, const std::vector<int>& faces,
                                     const std::function<void(const Tessellation&)>& beside) {
  Layout layout = layout_from_json(image.layout);
  if (!image.layout.contains("base_mesh"))
    throw InputError("the SDM header has no base mesh: it was written by an older 'sdm encode'; encode it again");
  const BaseMesh base = base_mesh_from_json(image.layout.at("base_mesh"), int(layout.segments.size()));
  if (layout.size != image.width || layout.size != image.height)
    throw InputError("the SDM image is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                     " but its layout is for a " + std::to_string(layout.size) + " atlas");
  // A posed skeleton is checked first: a wrong graph is refused before the work.
  if (options.skeleton) pose_skeleton(layout.skeleton, *options.skeleton);

  const std::vector<int> level = segment_levels(int(layout.segments.size()), options);
  Tessellation tess = tessellate_faces(base, level, faces);
  std::optional<BackgroundTask> task;  // joined before tess moves out (or when an exception unwinds)
  if (beside) task.emplace([&] { beside(tess); });
  std::vector<CapsuleFrame> frames;
  for (size_t s = 0; s < layout.segments.size(); ++s) frames.push_back(capsule_frame(layout, int(s)));
  const std::vector<std::array<Eigen::Vector3d, 3>> reference = reference_corners(base, layout, frames);
  // Where a base face's corners land: their (u, v) are exact, and so is their displacement where
  // the file stores it (format 3); older files read it from the map.
  auto ray_at = [&](int s, const Eigen::Vector3d& q) {
    const LayoutSegment& seg = layout.segments[s];
    const CapsuleUV uv = capsule_uv(frames[s], seg.w, seg.h, seg.d, q);
    return std::make_pair(capsule_ray(frames[s], seg.w, seg.h, seg.d, uv.u, uv.v), uv);
  };
  if (image.residual && base.corner_d.empty())
    throw InputError("the SDM stores residuals but its base mesh has no corner displacements: the file is damaged");
  std::vector<std::array<Eigen::Vector3d, 3>> corner(base.triangles.rows());
  for (int f = 0; f < base.triangles.rows(); ++f) {
    const int s = base.face_segment[f];
    for (int c = 0; c < 3; ++c) {
      const auto [ray, uv] = ray_at(s, reference[f][c]);
      const double d = base.corner_d.empty() ? sample_displacement(image, layout.segments[s], uv.u, uv.v) : base.corner_d[f][c];
      corner[f][c] = ray.origin + d * ray.direction;
    }
  }
  const std::vector<double> reach = face_reach(corner);
  // Rays and flat points of every decoded point, then the texels their lookups need, then the
  // points, each stage in parallel; the mesh is built in order.
  const size_t n = tess.point_face.size();
  std::vector<PointRay> at(n);
  parallel_for(int(n), 4096, [&](int i) {
    const int f = tess.point_face[size_t(i)];
    const Eigen::Vector3d& b = tess.point_bary[size_t(i)];
    PointRay& p = at[size_t(i)];
    p.segment = base.face_segment[f];
    p.flat = b[0] * corner[f][0] + b[1] * corner[f][1] + b[2] * corner[f][2];
    // The ray through the flat point itself, so that the decoded point only moves along it onto
    // the surface and the points keep the flat face's even spacing. Interpolating on the reference
    // triangle instead spaced them evenly on the capsule: where the surface lies far from the
    // capsule or across its rays they spread unevenly, and two segments on either side of a base
    // edge spread them differently (decoded edges up to 1.6-2 times the input's longest on the
    // paper's tubes; now at most 0.9: DECISIONS 4).
    const auto [ray, uv] = ray_at(p.segment, p.flat);
    p.ray = ray, p.u = uv.u, p.v = uv.v;
  });
  TexelReads reads(image, layout, base, corner);
  reads.prepare(at, tess.point_face, reach);
  const std::vector<Eigen::Vector3d> normal = base_vertex_normals(base, corner);
  const std::vector<char> flat = flat_points(base, tess);
  std::vector<Eigen::Vector3d> placed(n);
  parallel_for(int(n), 4096, [&](int i) {
    const PointRay& a = at[size_t(i)];
    const int f = tess.point_face[size_t(i)];
    // Flat faces' points, and every base corner where the file stores its displacement (exact).
    const bool corner = !base.corner_d.empty() && tess.point_bary[size_t(i)].maxCoeff() > 1 - 1e-9;
    if (corner || (!flat.empty() && flat[size_t(i)])) {
      placed[size_t(i)] = a.flat;
      return;
    }
    const double r = reach[f];
    const double d = sample_own_texels(base, layout.segments[a.segment], reads, size_t(i), f, a.u, a.v);
    // No texel left, or a depth of 0 (the encoder's foot clamped at the ray's origin: every ray of a
    // cap starts at its centre, so such points coincide and make zero-area faces): the flat point.
    Eigen::Vector3d p = !(d > 0) ? a.flat : Eigen::Vector3d(a.ray.origin + d * a.ray.direction);
    // Safeguard: near junctions a texel's ray can leave the segment's region and meet a far
    // surface; a point displaced farther from its decoded base triangle than half the triangle's
    // longest edge is such a point, and the flat base triangle's own point is the better estimate
    // (pulling it back only to that distance left Spot's 1024 map at RMS 0.020 %, Hausdorff 0.98 %;
    // the flat point gives 0.011 % and 0.55 %: DECISIONS 4).
    if ((p - a.flat).norm() > r) p = a.flat;
    if (p != a.flat) {
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      for (int c = 0; c < 3; ++c) n += tess.point_bary[size_t(i)][c] * normal[size_t(base.triangles(f, c))];
      const LayoutSegment& seg = layout.segments[a.segment];
      p = along_normal(a, n.normalized(), p, r, [&](const Eigen::Vector3d& x, double& below) {
        const auto [ray, uv] = ray_at(a.segment, x);
        const double d = sample_own_texels(base, seg, reads, size_t(i), f, uv.u, uv.v);
        below = d - (x - ray.origin).dot(ray.direction);
        return !std::isnan(d);
      });
    }
    placed[size_t(i)] = p;
  });
  if (task) task->wait();
  DecodedSurface out;
  out.points = std::move(placed);
  out.triangles = std::move(tess.triangles);
  out.point_face = std::move(tess.point_face);
  out.triangle_face = std::move(tess.triangle_face);
  out.point_segment.resize(n);
  for (size_t i = 0; i < n; ++i) out.point_segment[i] = at[i].segment;
  out.untangle = untangle_decoded(out.points, flat_points_of(at), out.triangles, out.triangle_face, base.triangles, out.point_segment);
  // Decoded at rest, then posed by the segments' blended motions (deform_decoded.h).
  if (options.skeleton) pose_points(layout, *options.skeleton, out.point_segment, out.triangles, out.points);
  return out;
}

}  // namespace

DecodedSurface decode_surface(const SdmImage& image, const DecodeOptions& options, const std::vector<int>& faces) {
  return decode_surface_beside(image, options, faces, {});
}

Eigen::MatrixX3d point_matrix(const DecodedSurface& surface) {
  Eigen::MatrixX3d P(Eigen::Index(surface.points.size()), 3);
  for (size_t i = 0; i < surface.points.size(); ++i) P.row(Eigen::Index(i)) = surface.points[i].transpose();
  return P;
}

Mesh decode_sdm(const SdmImage& image, const DecodeOptions& options, DecodeTrace* trace) {
  // The connectivity depends on the triangles alone: it is built while the points are placed, and
  // the points are set once they are (the placement keeps both cores busy, so the gain is small:
  // level 3 of a 30k and a 449k map 0.21-0.22 -> 0.20-0.21 s and 0.33-0.37 -> 0.28-0.34 s).
  Mesh out;
  DecodedSurface s = decode_surface_beside(image, options, {}, [&out](const Tessellation& tess) {
    const size_t n = tess.point_face.size(), nf = size_t(tess.triangles.rows());
    out.reserve(n, nf * 3 / 2 + 3, nf);
    for (size_t i = 0; i < n; ++i) out.add_vertex(Mesh::Point(0, 0, 0));
    std::vector<std::array<int, 3>> corners(nf);
    for (size_t t = 0; t < nf; ++t) corners[t] = {tess.triangles(Eigen::Index(t), 0), tess.triangles(Eigen::Index(t), 1), tess.triangles(Eigen::Index(t), 2)};
    add_faces_or_each(out, corners);  // add_face's connectivity, built faster (add_faces.h)
  });
  for (auto v : out.vertices()) {
    const Eigen::Vector3d& p = s.points[size_t(v.idx())];
    out.set_point(v, Mesh::Point(p.x(), p.y(), p.z()));
  }
  if (trace) {
    trace->vertex_segment = std::move(s.point_segment);
    trace->vertex_base_face = std::move(s.point_face);
    trace->face_base_face = std::move(s.triangle_face);
    trace->untangle = std::move(s.untangle);
  }
  return out;
}

}  // namespace sdm
