// collapse_ok answers what OpenMesh's is_collapse_ok answers, on every halfedge of closed and open
// meshes and while a mesh is being collapsed (deleted elements, boundary vertices, valence-3
// vertices), so the isotropic remesh that uses it collapses exactly the same edges.
#include "libstm/mesh/collapse_ok.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/primitives.h"
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
