#include "libstm/mesh/isotropic_remesh.h"

#include "libstm/core/parallel.h"
#include "libstm/mesh/collapse_ok.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

namespace sdm {
namespace {

using Vec = Eigen::Vector3d;

Vec P(const Mesh& m, Mesh::VertexHandle v) { return point(m, v); }
void set_P(Mesh& m, Mesh::VertexHandle v, const Vec& p) { m.set_point(v, Mesh::Point(p.x(), p.y(), p.z())); }

Vec tri_normal(const Vec& a, const Vec& b, const Vec& c) { return (b - a).cross(c - a); }

// Cosine of the angle between two (unnormalised) vectors; -1 when either is degenerate, so that a
// degenerate result is always refused.
double cos_between(const Vec& a, const Vec& b) {
  double n = a.norm() * b.norm();
  return n > 0 ? a.dot(b) / n : -1.0;
}

// Minimum cosine between a folded-over triangle's normal before and after an operation. Adjacent
// normals of a reasonably sampled smooth surface differ by far less than this.
constexpr double kFoldCos = 0.2;

// In passes over the edges that exist when the pass starts: splitting new edges at once can run
// away on needle triangles (each split of an edge next to a needle's far vertex makes another
// long edge), while a bounded number of passes always ends; the later steps clean up the rest.
void split_long_edges(Mesh& mesh, double high) {
  const double high2 = high * high;
  for (int pass = 0; pass < 10; ++pass) {
    bool split_any = false;
    const size_t existing = mesh.n_edges();
    for (size_t i = 0; i < existing; ++i) {
      auto e = mesh.edge_handle(static_cast<int>(i));
      if (mesh.status(e).deleted()) continue;
      auto h = mesh.halfedge_handle(e, 0);
      Vec a = P(mesh, mesh.from_vertex_handle(h)), b = P(mesh, mesh.to_vertex_handle(h));
      if ((a - b).squaredNorm() > high2) {
        Vec m = 0.5 * (a + b);
        mesh.split(e, Mesh::Point(m.x(), m.y(), m.z()));
        split_any = true;
      }
    }
    if (!split_any) break;
  }
}

// Collapsing h moves from(h) onto to(h). Refused when it would break the link condition, fold a
// tetrahedron flat (a small separate part), create an edge longer than `high` (with `relaxed`:
// longer than both `high` and 1.1 times v0's longest edge), or fold a triangle.
bool collapse_allowed(Mesh& mesh, Mesh::HalfedgeHandle h, double high2, bool relaxed = false) {
  if (!collapse_ok(mesh, h) || collapses_tetrahedron(mesh, h)) return false;
  auto v0 = mesh.from_vertex_handle(h), v1 = mesh.to_vertex_handle(h);
  Vec p0 = P(mesh, v0), p1 = P(mesh, v1);
  if (relaxed)
    for (auto w : mesh.vv_range(v0)) high2 = std::max(high2, 1.21 * (P(mesh, w) - p0).squaredNorm());
  for (auto w : mesh.vv_range(v0))
    if (w != v1 && (P(mesh, w) - p1).squaredNorm() > high2) return false;
  for (auto f : mesh.vf_range(v0)) {
    Vec c[3];
    bool has_v1 = false;
    int k = 0, i0 = -1;
    for (auto u : mesh.fv_range(f)) {
      if (u == v1) has_v1 = true;
      if (u == v0) i0 = k;
      c[k++] = P(mesh, u);
    }
    if (has_v1) continue;  // removed by the collapse
    Vec before = tri_normal(c[0], c[1], c[2]);
    c[i0] = p1;
    Vec after = tri_normal(c[0], c[1], c[2]);
    if (cos_between(before, after) < kFoldCos) return false;
  }
  return true;
}

void collapse_short_edges(Mesh& mesh, double low, double high, bool relaxed = false) {
  const double low2 = low * low, high2 = high * high;
  for (size_t i = 0; i < mesh.n_edges(); ++i) {
    auto e = mesh.edge_handle(static_cast<int>(i));
    if (mesh.status(e).deleted()) continue;
    auto h0 = mesh.halfedge_handle(e, 0), h1 = mesh.halfedge_handle(e, 1);
    Vec a = P(mesh, mesh.from_vertex_handle(h0)), b = P(mesh, mesh.to_vertex_handle(h0));
    if ((a - b).squaredNorm() >= low2) continue;
    // Keep the vertex of higher valence: removing the lower one moves the valences towards 6.
    auto va = mesh.from_vertex_handle(h0), vb = mesh.to_vertex_handle(h0);
    Mesh::HalfedgeHandle first = mesh.valence(va) <= mesh.valence(vb) ? h0 : h1;
    Mesh::HalfedgeHandle second = first == h0 ? h1 : h0;
    if (collapse_allowed(mesh, first, high2, relaxed))
      mesh.collapse(first);
    else if (collapse_allowed(mesh, second, high2, relaxed))
      mesh.collapse(second);
  }
  mesh.garbage_collection();
}

struct Quad {
  Mesh::VertexHandle a, b, c, d;  // edge a-b (halfedge b->a), c opposite in its face, d in the other
};

Quad quad_of(const Mesh& mesh, Mesh::EdgeHandle e) {
  auto h = mesh.halfedge_handle(e, 0);
  auto o = mesh.opposite_halfedge_handle(h);
  return {mesh.to_vertex_handle(h), mesh.from_vertex_handle(h), mesh.to_vertex_handle(mesh.next_halfedge_handle(h)),
          mesh.to_vertex_handle(mesh.next_halfedge_handle(o))};
}

// Faces (b, a, c) and (a, b, d) become (b, d, c) and (d, a, c); refused when that folds the surface.
bool flip_keeps_shape(const Mesh& mesh, const Quad& q) {
  Vec a = P(mesh, q.a), b = P(mesh, q.b), c = P(mesh, q.c), d = P(mesh, q.d);
  Vec n_old = tri_normal(b, a, c).normalized() + tri_normal(a, b, d).normalized();
  Vec n1 = tri_normal(b, d, c), n2 = tri_normal(d, a, c);
  return cos_between(n1, n2) > kFoldCos && cos_between(n1, n_old) > kFoldCos && cos_between(n2, n_old) > kFoldCos;
}

void equalize_valences(Mesh& mesh) {
  for (auto e : mesh.edges()) {
    if (mesh.status(e).deleted() || !mesh.is_flip_ok(e)) continue;
    Quad q = quad_of(mesh, e);
    int va = static_cast<int>(mesh.valence(q.a)), vb = static_cast<int>(mesh.valence(q.b));
    int vc = static_cast<int>(mesh.valence(q.c)), vd = static_cast<int>(mesh.valence(q.d));
    int before = std::abs(va - 6) + std::abs(vb - 6) + std::abs(vc - 6) + std::abs(vd - 6);
    int after = std::abs(va - 7) + std::abs(vb - 7) + std::abs(vc - 5) + std::abs(vd - 5);
    if (after < before && flip_keeps_shape(mesh, q)) mesh.flip(e);
  }
}

double angle_at(const Vec& apex, const Vec& p, const Vec& q) {
  Vec u = (p - apex).normalized(), v = (q - apex).normalized();
  return std::acos(std::clamp(u.dot(v), -1.0, 1.0));
}

// Intrinsic Delaunay flips: an edge whose two opposite angles sum to more than pi is replaced by
// the other diagonal, which maximises the smallest angle of the pair.
int delaunay_flips(Mesh& mesh) {
  int flips = 0;
  for (auto e : mesh.edges()) {
    if (mesh.status(e).deleted() || !mesh.is_flip_ok(e)) continue;
    Quad q = quad_of(mesh, e);
    Vec a = P(mesh, q.a), b = P(mesh, q.b), c = P(mesh, q.c), d = P(mesh, q.d);
    if (angle_at(c, a, b) + angle_at(d, a, b) > M_PI + 1e-9 && flip_keeps_shape(mesh, q)) {
      mesh.flip(e);
      ++flips;
    }
  }
  return flips;
}

void relax_and_project(Mesh& mesh, const SurfaceProjection& project) {
  std::vector<Vec> next(mesh.n_vertices());
  for (auto v : mesh.vertices()) {
    Vec p = P(mesh, v), centroid = Vec::Zero(), normal = Vec::Zero();
    int n = 0;
    for (auto w : mesh.vv_range(v)) {
      centroid += P(mesh, w);
      ++n;
    }
    for (auto f : mesh.vf_range(v)) {
      auto it = mesh.cfv_begin(f);
      Vec a = P(mesh, *it), b = P(mesh, *++it), c = P(mesh, *++it);
      normal += tri_normal(a, b, c);
    }
    if (n == 0 || normal.norm() == 0) {
      next[v.idx()] = p;
      continue;
    }
    normal.normalize();
    Vec move = centroid / n - p;
    next[v.idx()] = p + move - normal * normal.dot(move);
  }
  // Each vertex projected on its own (the closest point of a 900k-triangle surface: 5 us), on both
  // cores; the positions are the same whichever thread projects them.
  if (project) parallel_for(int(next.size()), 256, [&](int i) { next[size_t(i)] = project(next[size_t(i)]); });
  for (auto v : mesh.vertices()) set_P(mesh, v, next[v.idx()]);
}

// The vertices the first split would add: one per `high` of every longer edge.
double split_vertices(const Mesh& mesh, double high) {
  double n = 0;
  for (auto e : mesh.edges()) n += std::max(0.0, std::ceil(mesh.calc_edge_length(e) / high) - 1);
  return n;
}

}  // namespace

void isotropic_remesh(Mesh& mesh, double target_edge_length, int iterations, const SurfaceProjection& project) {
  const double low = 0.8 * target_edge_length, high = 4.0 / 3.0 * target_edge_length;
  // Needles (a CAD cylinder's 10000 side quads, 3 long and 6e-4 wide) would make the first split
  // multiply the mesh (10000-gon prism: 530k vertices, 71 s as a skeleton proxy). Their short
  // edges go first then, with collapses that may lengthen the long edges they already have by
  // 10 % (without that margin a neighbour's needle is a little longer and 70 % of the collapses
  // were refused): the prism's 20000 vertices become 117, and its proxy takes 0.5 s.
  if (split_vertices(mesh, high) > 2.0 * mesh.n_vertices()) collapse_short_edges(mesh, low, high, true);
  for (int it = 0; it < iterations; ++it) {
    split_long_edges(mesh, high);
    collapse_short_edges(mesh, low, high);
    equalize_valences(mesh);
    relax_and_project(mesh, project);
  }
  for (int round = 0; round < 3; ++round) {
    delaunay_flips(mesh);
    relax_and_project(mesh, project);
  }
  for (int round = 0; round < 5 && delaunay_flips(mesh) > 0; ++round) {
  }
  mesh.garbage_collection();
}

double min_triangle_angle_degrees(const Mesh& mesh) {
  double best = M_PI;
  for (auto f : mesh.faces()) {
    auto it = mesh.cfv_begin(f);
    Vec a = P(mesh, *it), b = P(mesh, *++it), c = P(mesh, *++it);
    best = std::min({best, angle_at(a, b, c), angle_at(b, c, a), angle_at(c, a, b)});
  }
  return best * 180.0 / M_PI;
}

}  // namespace sdm
