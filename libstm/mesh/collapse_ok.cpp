#include "libstm/mesh/collapse_ok.h"

namespace sdm {
namespace {

// The far corner of the face of h (h not on the boundary); false when both of that face's other
// sides lie on the boundary (the collapse would leave a dangling face).
bool far_corner(const Mesh& mesh, Mesh::HalfedgeHandle h, Mesh::VertexHandle& corner) {
  const auto h1 = mesh.next_halfedge_handle(h), h2 = mesh.next_halfedge_handle(h1);
  corner = mesh.to_vertex_handle(h1);
  return !(mesh.is_boundary(mesh.opposite_halfedge_handle(h1)) && mesh.is_boundary(mesh.opposite_halfedge_handle(h2)));
}

}  // namespace

bool collapse_ok(const Mesh& mesh, Mesh::HalfedgeHandle v0v1) {
  if (mesh.status(mesh.edge_handle(v0v1)).deleted()) return false;
  const auto v1v0 = mesh.opposite_halfedge_handle(v0v1);
  const auto v0 = mesh.to_vertex_handle(v1v0), v1 = mesh.to_vertex_handle(v0v1);
  if (mesh.status(v0).deleted() || mesh.status(v1).deleted()) return false;
  Mesh::VertexHandle vl, vr;
  if (!mesh.is_boundary(v0v1) && !far_corner(mesh, v0v1, vl)) return false;
  if (!mesh.is_boundary(v1v0) && !far_corner(mesh, v1v0, vr)) return false;
  if (vl == vr) return false;
  // The one-rings of v0 and v1 may share only vl and vr. Valences are small: v1's ring is walked
  // once per neighbour of v0 rather than tagged.
  const auto h0 = mesh.halfedge_handle(v0), g0 = mesh.halfedge_handle(v1);
  auto h = h0;
  do {
    const auto a = mesh.to_vertex_handle(h);
    if (a != vl && a != vr) {
      auto g = g0;
      do {
        if (mesh.to_vertex_handle(g) == a) return false;
        g = mesh.next_halfedge_handle(mesh.opposite_halfedge_handle(g));
      } while (g != g0);
    }
    h = mesh.next_halfedge_handle(mesh.opposite_halfedge_handle(h));
  } while (h != h0);
  return !(mesh.is_boundary(v0) && mesh.is_boundary(v1) && !mesh.is_boundary(v0v1) && !mesh.is_boundary(v1v0));
}

bool collapses_tetrahedron(const Mesh& mesh, Mesh::HalfedgeHandle v0v1) {
  const auto v0 = mesh.from_vertex_handle(v0v1), v1 = mesh.to_vertex_handle(v0v1);
  return mesh.valence(v0) == 3 && mesh.valence(v1) == 3 && !mesh.is_boundary(v0) && !mesh.is_boundary(v1);
}

}  // namespace sdm
