// collapse_ok answers what OpenMesh's is_collapse_ok answers, on every halfedge of closed and open
// meshes and while a mesh is being collapsed (deleted elements, boundary vertices, valence-3
// vertices), so the isotropic remesh that uses it collapses exactly the same edges.
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/mesh/collapse_ok.h"
#include "libstm/mesh/isotropic_remesh.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/primitives.h"
#include "libstm/mesh/validate_mesh.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>
#include <random>

using namespace sdm;

namespace {

// Halfedges where the two answers differ, over the whole mesh.
int disagreements(Mesh& m) {
  int differ = 0;
  for (auto h : m.halfedges()) differ += collapse_ok(m, h) != m.is_collapse_ok(h);
  return differ;
}

// The mesh with the faces around `holes` spread vertices removed: open, with boundary loops.
Mesh with_holes(const Mesh& closed, int holes) {
  Mesh m = closed;
  m.request_face_status();
  m.request_edge_status();
  m.request_vertex_status();
  for (int k = 0; k < holes; ++k) {
    const Mesh::VertexHandle v(int(size_t(k) * m.n_vertices() / size_t(holes)));
    std::vector<Mesh::FaceHandle> ring(m.vf_begin(v), m.vf_end(v));
    for (auto f : ring)
      if (!m.status(f).deleted()) m.delete_face(f, false);
  }
  m.garbage_collection();
  return m;
}

// Random collapses that OpenMesh allows, checking both answers on the whole mesh every `every`.
int disagreements_while_collapsing(Mesh m, int collapses, int every) {
  m.request_face_status();
  m.request_edge_status();
  m.request_vertex_status();
  std::mt19937 rng(7);
  int differ = 0;
  for (int done = 0, tries = 0; done < collapses && tries < 50 * collapses; ++tries) {
    const Mesh::HalfedgeHandle h(int(rng() % m.n_halfedges()));
    if (!m.is_collapse_ok(h)) continue;
    m.collapse(h);
    if (++done % every == 0) differ += disagreements(m);
  }
  return differ;
}

}  // namespace

TEST_CASE("collapse_ok gives OpenMesh's answer on every halfedge", "[collapse_ok]") {
  for (const char* name : {"capsule", "cylinder", "donut", "ypsilon", "triple-torus"}) {
    INFO(name);
    Mesh closed = make_primitive(name);
    closed.request_vertex_status(), closed.request_edge_status(), closed.request_face_status();
    CHECK(disagreements(closed) == 0);
    Mesh open = with_holes(closed, 5);
    CHECK(disagreements(open) == 0);
    CHECK(disagreements_while_collapsing(closed, int(closed.n_vertices()) * 3 / 4, 50) == 0);
    CHECK(disagreements_while_collapsing(open, int(open.n_vertices()) * 3 / 4, 50) == 0);
  }
  for (const auto& shared : test_util::closed_shared_meshes()) {
    INFO(shared.name);
    Mesh m = load_mesh(shared.path).mesh;
    m.request_vertex_status(), m.request_edge_status(), m.request_face_status();
    CHECK(disagreements(m) == 0);
    Mesh open = with_holes(m, 7);
    CHECK(disagreements(open) == 0);
  }
}

TEST_CASE("collapse_ok on the smallest open meshes", "[collapse_ok]") {
  // A single triangle: every side's face has both other sides on the boundary.
  Mesh tri;
  const auto a = tri.add_vertex({0, 0, 0}), b = tri.add_vertex({1, 0, 0}), c = tri.add_vertex({0, 1, 0});
  tri.add_face(a, b, c);
  tri.request_vertex_status(), tri.request_edge_status(), tri.request_face_status();
  for (auto h : tri.halfedges()) CHECK_FALSE(collapse_ok(tri, h));
  CHECK(disagreements(tri) == 0);
  // Two triangles sharing an edge: every vertex on the boundary, the shared edge inside.
  Mesh quad;
  const auto p = quad.add_vertex({0, 0, 0}), q = quad.add_vertex({1, 0, 0}), r = quad.add_vertex({1, 1, 0}), s = quad.add_vertex({0, 1, 0});
  quad.add_face(p, q, r);
  quad.add_face(p, r, s);
  quad.request_vertex_status(), quad.request_edge_status(), quad.request_face_status();
  CHECK_FALSE(collapse_ok(quad, quad.find_halfedge(p, r)));  // both ends on the boundary, the edge not
  CHECK(disagreements(quad) == 0);
}

TEST_CASE("no collapse folds a tetrahedron flat: a small separate part stays closed", "[collapse_ok]") {
  // The link condition lets every edge of a tetrahedron go; the result would be two faces on the
  // same three corners.
  Mesh tet;
  const auto a = tet.add_vertex({0, 0, 0}), b = tet.add_vertex({1, 0, 0}), c = tet.add_vertex({0, 1, 0}), d = tet.add_vertex({0, 0, 1});
  tet.add_face(a, c, b), tet.add_face(a, b, d), tet.add_face(a, d, c), tet.add_face(b, c, d);
  tet.request_vertex_status(), tet.request_edge_status(), tet.request_face_status();
  for (auto h : tet.halfedges()) CHECK(collapse_ok(tet, h));
  for (auto h : tet.halfedges()) CHECK(collapses_tetrahedron(tet, h));
  // A capsule with a copy fifty times smaller beside it, remeshed at an edge length longer than the
  // small copy: both parts stay closed 2-manifolds of genus 0, the small one four faces at least.
  const Mesh big = make_primitive("capsule");
  Mesh m = big;
  const int n = int(big.n_vertices());
  for (auto v : big.vertices()) m.add_vertex(big.point(v) * 0.02f + Mesh::Point(5, 0, 0));
  for (auto f : big.faces()) {
    std::vector<Mesh::VertexHandle> corners;
    for (auto v : big.fv_range(f)) corners.push_back(Mesh::VertexHandle(v.idx() + n));
    m.add_face(corners);
  }
  for (auto h : m.halfedges()) CHECK_FALSE(collapses_tetrahedron(m, h));
  double longest = 0;
  for (auto e : big.edges()) longest = std::max(longest, double(big.calc_edge_length(e)));
  const TriangleBvh surface(vertex_matrix(m), face_matrix(m));
  isotropic_remesh(m, 2 * longest, 5, [&](const Eigen::Vector3d& p) { return surface.closest_point(p).point; });
  const MeshReport r = validate_mesh(mesh_to_soup(m));
  CHECK(r.usable());
  CHECK(r.genus_per_part == std::vector<int>{0, 0});
  for (const Finding& f : r.findings) CHECK(f.id == "parts");  // no duplicated faces among them
  REQUIRE(r.faces_per_part.size() == 2);
  CHECK(std::min(r.faces_per_part[0], r.faces_per_part[1]) >= 4);
}
