#include "libsdm/encode/base_mesh.h"

#include "libstm/core/errors.h"
#include "libstm/core/json_int.h"
#include "libstm/core/parallel.h"
#include "libstm/core/stopwatch.h"
#include "libstm/geometry/capsule_ray.h"
#include "libstm/layout/assign_layout_faces.h"
#include "libstm/layout/segments.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/geometry/working_origin.h"
#include "libstm/mesh/collapse_ok.h"
#include "libstm/mesh/isotropic_remesh.h"
#include "libstm/mesh/spatial_order.h"
#include "libstm/mesh/mesh_geometry.h"

#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/MixedDecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>

namespace sdm {
namespace {

// Keeps every base face within reach of one segment: a collapse may only join vertices whose
// skeleton nodes are the same or neighbours. Quadric decimation alone runs slivers the length of a
// straight tube (a cylinder is flat along its axis), across many short segments, and a face its
// segment's capsule cannot reach is decoded as spikes.
template <class MeshT>
class ModSkeletonNodesT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModSkeletonNodesT, MeshT, SkeletonNodes);
  explicit ModSkeletonNodesT(MeshT& mesh) : Base(mesh, true) {}
  // node: skeleton node of each vertex of the mesh (a vertex property, so that it survives garbage
  // collection between rounds); adjacent: the skeleton's edges, both directions.
  void set_nodes(OpenMesh::VPropHandleT<int> node, std::set<std::pair<int, int>> adjacent) {
    node_ = node;
    adjacent_ = std::move(adjacent);
  }
  float collapse_priority(const CollapseInfo& ci) override {
    const MeshT& m = this->mesh();
    const int keep = m.property(node_, ci.v1);
    for (auto x : m.vv_range(ci.v0)) {
      const int other = m.property(node_, x);
      if (other != keep && !adjacent_.count({keep, other})) return float(Base::ILLEGAL_COLLAPSE);
    }
    return float(Base::LEGAL_COLLAPSE);
  }

 private:
  OpenMesh::VPropHandleT<int> node_;
  std::set<std::pair<int, int>> adjacent_;
};

// Forbids collapses that would make an edge longer than a limit. The decoder's default level cuts
// every base edge into 8, so base edges up to 8 times the input's longest edge decode to pieces no
// longer than the input's longest on the flat face (quadric decimation of the paper's
// crossed cylinders ran base faces 1.7 long along the flat tubes, and level 3 left edges of 0.22
// where the input's longest is 0.12). The limit is 7 times: the surface bulges out of a flat face,
// and its decoded pieces are longer than the flat ones (at 8 times, with the decoder's rays through
// the flat points: the crossed cylinders' and the two-tunnels bar's longest decoded edges 1.00 and
// 1.12 times the input's; at 7, 0.88 and 0.89; at 6 the bottle's Hausdorff 0.51 -> 0.55 %).
constexpr double kMaxBaseEdge = 7.0;
template <class MeshT>
class ModMaxEdgeLengthT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModMaxEdgeLengthT, MeshT, MaxEdgeLength);
  explicit ModMaxEdgeLengthT(MeshT& mesh) : Base(mesh, true) {}
  void set_max_length(double length) { max_sq_ = length * length; }
  float collapse_priority(const CollapseInfo& ci) override {
    for (auto x : this->mesh().vv_range(ci.v0))
      if (x != ci.v1 && (this->mesh().point(x) - ci.p1).sqrnorm() > max_sq_) return float(Base::ILLEGAL_COLLAPSE);
    return float(Base::LEGAL_COLLAPSE);
  }

 private:
  double max_sq_ = INFINITY;
};

// Keeps an open mesh's boundary loops where they are: a boundary vertex may only move
// along its loop, onto a neighbour on the loop, and only when the loop's new edge passes within
// `tolerance` of it. The decoder places points of a base boundary edge on the rays through the
// flat edge, so the distance between the base loop and the input's is the error at the holes.
template <class MeshT>
class ModBoundaryT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModBoundaryT, MeshT, Boundary);
  explicit ModBoundaryT(MeshT& mesh) : Base(mesh, true) {}
  void set_tolerance(double tolerance) { tolerance_ = tolerance; }
  float collapse_priority(const CollapseInfo& ci) override {
    const MeshT& m = this->mesh();
    if (!m.is_boundary(ci.v0)) return float(Base::LEGAL_COLLAPSE);
    if (!m.is_boundary(m.edge_handle(ci.v0v1))) return float(Base::ILLEGAL_COLLAPSE);
    // v0's other neighbour on its loop: the new edge runs from it to v1.
    for (auto h : m.voh_range(ci.v0)) {
      const auto w = m.to_vertex_handle(h);
      if (w == ci.v1 || !m.is_boundary(m.edge_handle(h))) continue;
      const Eigen::Vector3d a = point(m, w), b = point(m, ci.v1), p = point(m, ci.v0);
      const Eigen::Vector3d ab = b - a;
      const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
      if ((a + t * ab - p).norm() > tolerance_) return float(Base::ILLEGAL_COLLAPSE);
    }
    return float(Base::LEGAL_COLLAPSE);
  }

 private:
  double tolerance_ = 0;
};

// Whether segment s can carry base face f alone along its rays. The decoder places a point of f on
// the ray of s through it, at the depth the map stores for that ray: a ray holds one depth, so f
// fails when it is turned away from the rays (its reference triangle is flipped or edge-on), or
// when the rays through it also cross another face of s at another depth (the surface folds back
// over f as seen from the axis: f is the farther sheet, or, with `both`, either sheet).
class SegmentCheck {
 public:
  SegmentCheck(const Eigen::MatrixX3d& P, const Eigen::MatrixX3i& T, const std::vector<int>& orient, const Layout& layout)
      : P_(P), T_(T), orient_(orient), layout_(layout) {}

  void set_faces(int s, const std::vector<int>& faces) {
    bvh_.resize(layout_.segments.size());
    bvh_[s] = TriangleBvh(P_, T_, faces);
  }

  bool fits(int f, int s, bool both) const {
    const LayoutSegment& seg = layout_.segments[s];
    const CapsuleFrame frame = capsule_frame(layout_, s);
    Eigen::Vector3d c[3];
    double longest = 0;
    for (int k = 0; k < 3; ++k) c[k] = P_.row(T_(f, k)).transpose();
    for (int k = 0; k < 3; ++k) longest = std::max(longest, (c[k] - c[(k + 1) % 3]).norm());
    // Orientation on the reference capsule, seen along the ray through the centroid.
    const Eigen::Vector3d centroid = (c[0] + c[1] + c[2]) / 3;
    Eigen::Vector3d r[3];
    for (int k = 0; k < 3; ++k) {
      const CapsuleUV uv = capsule_uv(frame, seg.w, seg.h, seg.d, c[k]);
      const CapsuleRay ray = capsule_ray(frame, seg.w, seg.h, seg.d, uv.u, uv.v);
      r[k] = ray.origin + seg.radius * ray.direction;
    }
    const CapsuleUV cu = capsule_uv(frame, seg.w, seg.h, seg.d, centroid);
    const CapsuleRay cray = capsule_ray(frame, seg.w, seg.h, seg.d, cu.u, cu.v);
    const Eigen::Vector3d n = (r[1] - r[0]).cross(r[2] - r[0]);
    if (!(orient_[f] * n.dot(cray.direction) > kMinCosine * n.norm())) return false;
    // A face wrapped far around the axis (one the axis runs through or next to) has a reference
    // triangle cutting through the capsule's inside: its rays fan out over the whole face.
    if (distance_to_segment((r[0] + r[1] + r[2]) / 3, frame.a, frame.b) < kMinDepth * seg.radius) return false;
    if (bvh_[s].empty()) return true;
    // Other crossings of s along the rays through points of f: centroid, corners, edge midpoints,
    // and corners pushed a little outwards, because the decoder's bilinear lookups at f's border
    // read texels just outside f.
    const double tol = 0.25 * longest;
    for (int k = 0; k < 10; ++k) {
      const Eigen::Vector3d q = k == 9 ? centroid
                                : k < 3 ? c[k]
                                : k < 6 ? Eigen::Vector3d(0.5 * (c[k - 3] + c[(k - 2) % 3]))
                                        : Eigen::Vector3d(c[k - 6] + 0.15 * (c[k - 6] - centroid));
      const CapsuleUV uv = capsule_uv(frame, seg.w, seg.h, seg.d, q);
      const CapsuleRay ray = capsule_ray(frame, seg.w, seg.h, seg.d, uv.u, uv.v);
      const double tq = (q - ray.origin).dot(ray.direction);
      double t_min = 0;
      for (int n_hit = 0; n_hit < 32; ++n_hit) {
        const auto hit = bvh_[s].first_hit(ray.origin, ray.direction, t_min);
        if (hit.face < 0) break;
        t_min = hit.t + 1e-9 * (1 + hit.t);
        if (hit.face == f || std::abs(hit.t - tq) <= tol) continue;
        if (hit.t < tq || both) return false;
      }
    }
    return true;
  }

 private:
  static constexpr double kMinCosine = 0.1;
  static constexpr double kMinDepth = 0.5;
  const Eigen::MatrixX3d& P_;
  const Eigen::MatrixX3i& T_;
  const std::vector<int>& orient_;
  const Layout& layout_;
  std::vector<TriangleBvh> bvh_;
};

// The segment each base face that its own segment cannot carry moves to: the nearest (by its
// centroid's distance to the segment's bone) that can carry it; -1 for faces that stay. Faces on
// both cores: within a round each face's answer reads only the check's trees, set for the round.
std::vector<int> refit_faces(const Eigen::MatrixX3d& P, const Eigen::MatrixX3i& T, const Layout& layout, const SegmentCheck& check,
                             const std::vector<int>& face_segment) {
  std::vector<int> moved_to(size_t(T.rows()), -1);
  const int S = int(layout.segments.size());
  parallel_for(int(T.rows()), 64, [&](int f) {
    if (check.fits(f, face_segment[f], false)) return;
    const Eigen::Vector3d centroid = (P.row(T(f, 0)) + P.row(T(f, 1)) + P.row(T(f, 2))).transpose() / 3;
    std::vector<std::pair<double, int>> near;
    for (int s = 0; s < S; ++s) {
      if (s == face_segment[f]) continue;
      const LayoutSegment& seg = layout.segments[s];
      near.push_back({distance_to_segment(centroid, layout.skeleton.nodes[seg.a], layout.skeleton.nodes[seg.b]), s});
    }
    std::sort(near.begin(), near.end());
    for (const auto& [dist, s] : near)
      if (check.fits(f, s, true)) {
        moved_to[size_t(f)] = s;
        break;
      }
  });
  return moved_to;
}

// Moves base faces that their segment cannot carry (SegmentCheck) to the nearest segment that can,
// without conflicting with that segment's faces. Faces no segment can carry stay.
void reassign_folded_faces(const Mesh& m, const Eigen::MatrixX3d& P, const Layout& layout, std::vector<int>& face_segment) {
  const Eigen::MatrixX3i T = face_matrix(m);
  const std::vector<int> orient = face_orientation(m);
  const int S = int(layout.segments.size());
  SegmentCheck check(P, T, orient, layout);
  for (int round = 0; round < 3; ++round) {
    std::vector<std::vector<int>> faces_of(S);
    for (int f = 0; f < T.rows(); ++f) faces_of[face_segment[f]].push_back(f);
    for (int s = 0; s < S; ++s) check.set_faces(s, faces_of[s]);
    const std::vector<int> moved_to = refit_faces(P, T, layout, check, face_segment);
    bool moved = false;
    for (size_t f = 0; f < moved_to.size(); ++f)
      if (moved_to[f] >= 0) face_segment[f] = moved_to[f], moved = true;
    if (!moved) break;
  }
}

// The share of faces with an angle under 1 degree.
double needle_share(const Mesh& mesh) {
  long needles = 0;
  for (auto f : mesh.faces()) {
    Eigen::Vector3d c[3];
    int k = 0;
    for (auto v : mesh.fv_range(f)) c[k++] = point(mesh, v);
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d a = c[(i + 1) % 3] - c[i], b = c[(i + 2) % 3] - c[i];
      if (std::atan2(a.cross(b).norm(), a.dot(b)) < M_PI / 180) {
        ++needles;
        break;
      }
    }
  }
  return mesh.n_faces() ? double(needles) / mesh.n_faces() : 0.0;
}

// What the base mesh is decimated from: the input and its skeleton nodes, or, when a quarter or more
// of its faces are needles (a CAD cylinder's side: 3000 quads 3 long and 2e-3 wide) or it has more
// than kRemeshSourceFrom vertices, an isotropic remesh of it with about four times the base mesh's
// vertices, each vertex on the input's surface with the node of the nearest corner of its closest
// input face. Decimating the needles themselves kept base faces the length of the part (a prism with
// 3000-gon caps: RMS 1.2 % at level 3, against 0.007 % from the remesh). A large closed mesh is
// remeshed because collapsing its own vertices one by one is the encode's cost: 449k vertices, encode
// stage 11.0-12.6 -> 6.9-7.4 s, the map's check at level 3 RMS 0.0067 -> 0.0074 % (DECISIONS 4,
// "Encoding large meshes").
constexpr int kRemeshSourceFrom = 100000;

struct BaseSource {
  Mesh mesh;
  std::vector<int> node;
};

BaseSource base_source(const Mesh& mesh, const Skeleton& skeleton, int target_vertices, const TriangleBvh* surface) {
  BaseSource src{mesh, skeleton.vertex_node};
  // The remesh needs a closed surface; an open mesh's needles are decimated as they are.
  const bool open = std::any_of(mesh.halfedges_begin(), mesh.halfedges_end(), [&](auto h) { return mesh.is_boundary(h); });
  if (open || (int(mesh.n_vertices()) <= kRemeshSourceFrom && needle_share(mesh) < 0.25)) return src;
  const Eigen::MatrixX3d V = vertex_matrix(mesh);
  const Eigen::MatrixX3i F = face_matrix(mesh);
  const double len = equilateral_edge_length(surface_area(mesh), 4.0 * target_vertices);
  const TriangleBvh own = surface ? TriangleBvh() : TriangleBvh(V, F);
  const TriangleBvh& bvh = surface ? *surface : own;
  if (int(mesh.n_vertices()) > kRenumberCopiesFrom && scattered_numbering(src.mesh)) src.mesh = spatially_ordered(src.mesh);
  isotropic_remesh(src.mesh, len, 5, [&](const Eigen::Vector3d& p) { return bvh.closest_point(p).point; });
  src.node.assign(src.mesh.n_vertices(), 0);
  for (auto v : src.mesh.vertices()) {
    const Eigen::Vector3d p = point(src.mesh, v);
    const int f = bvh.closest_point(p).face;
    int best = F(f, 0);
    for (int k = 1; k < 3; ++k)
      if ((V.row(F(f, k)).transpose() - p).squaredNorm() < (V.row(best).transpose() - p).squaredNorm()) best = F(f, k);
    src.node[v.idx()] = skeleton.vertex_node[best];
  }
  return src;
}

// How far a base mesh's boundary loop may stray from the input's, in bounding-box diagonals:
// measured on open meshes, within the round trip's Hausdorff at level 3 (DECISIONS 1, "Open meshes").
constexpr double kBoundaryTolerance = 0.002;

// Above this many vertices, and more than kMultipleChoiceFactor times the target, the decimation
// starts with multiple-choice collapses (Wu and Kobbelt 2002: the best of a few random candidates,
// no heap; 2 candidates while over 4 times that size, where every edge is far shorter than the
// base mesh's, then OpenMesh's 10) down to kMultipleChoiceFactor times the target, and the greedy
// heap finishes. The heap alone re-checks every neighbour's collapses after each collapse: 523k
// vertices to 4000 took 33 s of a 1024 encode's 37 s; now 8.3-10.8 s (DECISIONS 4,
// "Encoding large meshes"), the round trip as close (RMS 0.0156 -> 0.0142 %). From 20k vertices down
// to 3 times the target (was: from 100k, to 8 times): the 29,686-vertex bunny's encode 3.2 -> 2.7 s,
// RMS 0.0072 -> 0.0070 %, Hausdorff 0.236 -> 0.246 % (bunny00: 0.0065 / 0.212 -> 0.0066 / 0.235 %),
// the map 1-2 % larger (measured with the encoder's check of its map). Smaller meshes keep the
// heap alone.
constexpr int kMultipleChoiceFrom = 20000;
constexpr int kMultipleChoiceFactor = 3;

// The mesh the decimater runs on: sdm's mesh with the link condition answered by collapse_ok. The
// decimater, a template over the mesh, calls mesh_.is_collapse_ok for every candidate collapse it
// weighs, which this hides; OpenMesh 9's own allocates and looks a property up by name on each
// call (half of the heap's time: DECISIONS 6, "The remesh's link condition"). The same answers,
// and no tetrahedron folded flat (collapse_ok.h): a small separate part stays a closed part.
struct DecimationMesh : Mesh {
  explicit DecimationMesh(const Mesh& m) : Mesh(m) {}
  bool is_collapse_ok(HalfedgeHandle h) const { return collapse_ok(*this, h) && !collapses_tetrahedron(*this, h); }
};

// Decimates m to target_vertices with quadrics, no normal flips and collapses only between
// neighbouring skeleton nodes (node: m's vertex property of them; it survives the collections). Deterministic: the multiple-choice stage
// draws its candidates from rand(), seeded here (nothing else in sdm draws from it).
void decimate_base(DecimationMesh& m, OpenMesh::VPropHandleT<int> node, const Skeleton& skeleton, int target_vertices, double max_edge,
                   const Progress& progress) {
  m.request_face_normals();
  m.update_face_normals();
  OpenMesh::Decimater::MixedDecimaterT<DecimationMesh> decimater(m);
  OpenMesh::Decimater::ModQuadricT<DecimationMesh>::Handle quadric;
  OpenMesh::Decimater::ModNormalFlippingT<DecimationMesh>::Handle flipping;
  typename ModSkeletonNodesT<DecimationMesh>::Handle nodes;
  typename ModMaxEdgeLengthT<DecimationMesh>::Handle length;
  typename ModBoundaryT<DecimationMesh>::Handle boundary;
  decimater.add(quadric);
  decimater.add(boundary);
  decimater.module(boundary).set_tolerance(kBoundaryTolerance * bounding_box_diagonal(m));
  decimater.add(flipping);
  decimater.add(nodes);
  decimater.add(length);
  decimater.module(length).set_max_length(max_edge);
  std::set<std::pair<int, int>> adjacent;
  for (const auto& e : skeleton.edges) adjacent.insert({e[0], e[1]}), adjacent.insert({e[1], e[0]});
  decimater.module(nodes).set_nodes(node, std::move(adjacent));
  decimater.module(quadric).unset_max_err();
  decimater.module(flipping).set_max_normal_deviation(60.0);
  decimater.initialize();
  const size_t coarse = size_t(kMultipleChoiceFactor) * size_t(target_vertices);
  if (m.n_vertices() > size_t(kMultipleChoiceFrom) && m.n_vertices() > coarse) {
    std::srand(1);
    // Rounds that halve the vertices, the deleted ones collected after each: the candidates are
    // drawn from every halfedge slot, deleted or not.
    while (m.n_vertices() > coarse) {
      const size_t n = m.n_vertices(), goal = std::max(coarse, n / 2);
      decimater.set_samples(n > 4 * coarse ? 2 : 10);
      const Stopwatch round;
      const size_t done = decimater.McDecimaterT<DecimationMesh>::decimate(n - goal);
      m.garbage_collection();
      // Each round halves the vertices and takes about half as long as the one before, so what is
      // left takes about as long as this round did (plus the heap's last stretch).
      const double s = round.seconds();
      char line[160];
      std::snprintf(line, sizeof line, "base mesh: %zu -> %zu vertices in %.1f s (%.0f k collapses/s), about %.0f s left", n,
                    size_t(m.n_vertices()), s, double(done) / std::max(s, 1e-9) / 1e3, std::ceil(s));
      report_progress(progress, line);
      if (2 * done < n - goal) break;  // the candidates ran out of legal collapses: the heap finishes
    }
  }
  decimater.DecimaterT<DecimationMesh>::decimate_to(size_t(target_vertices));
  m.garbage_collection();
}

}  // namespace

struct BaseMeshSource::Impl {
  const Mesh& input;
  const Layout& layout;
  int target_vertices = 0;
  BaseSource src;
};

BaseMeshSource::BaseMeshSource(const Mesh& input, const Layout& layout, int target_vertices, const TriangleBvh* surface) {
  const int nv = int(input.n_vertices());
  // A quarter of the input's vertices, at least 800 (all of a smaller input's) and at most 4000. The
  // floor was 400: small models with sharp features then had base faces across their edges (the
  // 1148-vertex beetle at 1024 and level 3: RMS 0.0510 -> 0.0172 % of the diagonal, Suzanne 0.0292
  // -> 0.0171, the cow 0.0425 -> 0.0387; Spot, the teapot, the double torus unchanged; encoding
  // within 10 %: BENCHMARKS "Round trips of every real mesh").
  if (target_vertices <= 0) target_vertices = std::clamp(nv / 4, std::min(nv, 800), 4000);
  impl_.reset(new Impl{input, layout, target_vertices, base_source(input, layout.skeleton, target_vertices, surface)});
}

BaseMeshSource::~BaseMeshSource() = default;
BaseMeshSource::BaseMeshSource(BaseMeshSource&&) noexcept = default;

Eigen::MatrixX3d BaseMeshSource::points() const { return vertex_matrix(impl_->src.mesh); }

BaseMesh BaseMeshSource::decimate(const std::vector<char>& keep, const Progress& progress) const {
  const Layout& layout = impl_->layout;
  const BaseSource& src = impl_->src;
  // Halfedge collapses keep the surviving vertices where they were, so m's points are the source's.
  DecimationMesh m(src.mesh);
  OpenMesh::VPropHandleT<int> node;  // skeleton node of each base vertex
  m.add_property(node);
  m.request_vertex_status();
  int kept = 0;
  for (auto v : m.vertices()) {
    m.property(node, v) = src.node[size_t(v.idx())];
    if (!keep.empty() && keep[size_t(v.idx())]) m.status(v).set_locked(true), ++kept;
  }
  const int target = impl_->target_vertices + kept;
  // The decimater works on the mesh moved near the origin (working_origin.h: far from it the
  // quadrics' plane offsets cancel), and the vertices it keeps take back their own positions.
  OpenMesh::VPropHandleT<Mesh::Point> own;
  m.add_property(own);
  Eigen::Vector3d lo, hi;
  bounding_box(m, lo, hi);
  const Eigen::Vector3d shift = working_origin(lo, hi);
  const Mesh::Point centre(shift.x(), shift.y(), shift.z());
  for (auto v : m.vertices()) m.property(own, v) = m.point(v), m.point(v) -= centre;
  if (target < int(m.n_vertices())) decimate_base(m, node, layout.skeleton, target, kMaxBaseEdge * longest_edge(impl_->input), progress);
  for (auto v : m.vertices()) m.point(v) = m.property(own, v);
  if (m.has_face_normals()) m.update_face_normals();
  // Segments of the base faces: the skeleton's map restricted to the surviving vertices.
  Skeleton sk = layout.skeleton;
  sk.vertex_node.resize(m.n_vertices());
  for (auto v : m.vertices()) sk.vertex_node[v.idx()] = m.property(node, v);
  BaseMesh base;
  base.face_segment = assign_faces(m, layout, sk);
  reassign_folded_faces(m, vertex_matrix(m), layout, base.face_segment);
  base.triangles = face_matrix(m);
  base.corner_uv.resize(m.n_faces());
  base.corner_position.resize(m.n_faces());
  base.corner_d.resize(m.n_faces());
  for (auto f : m.faces()) {
    const int s = base.face_segment[f.idx()];
    const LayoutSegment& seg = layout.segments[s];
    const CapsuleFrame frame = capsule_frame(layout, s);
    int c = 0;
    for (auto v : m.fv_range(f)) {
      const Eigen::Vector3d p = point(m, v);
      const CapsuleUV uv = capsule_uv(frame, seg.w, seg.h, seg.d, p);
      const CapsuleRay ray = capsule_ray(frame, seg.w, seg.h, seg.d, uv.u, uv.v);
      base.corner_position[f.idx()][c] = p;
      base.corner_d[f.idx()][c] = (p - ray.origin).dot(ray.direction);
      base.corner_uv[f.idx()][c++] = {uv.u, uv.v};
    }
  }
  return base;
}

BaseMesh make_base_mesh(const Mesh& input, const Layout& layout, int target_vertices, const Progress& progress,
                        const TriangleBvh* surface) {
  return BaseMeshSource(input, layout, target_vertices, surface).decimate({}, progress);
}

}  // namespace sdm
