#include "libstm/skeleton/contraction_proxy.h"

#include "libstm/geometry/differential_geometry.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/geometry/vertex_normals.h"
#include "libstm/mesh/add_faces.h"
#include "libstm/mesh/isotropic_remesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/spatial_order.h"

#include <algorithm>
#include <cmath>

namespace sdm {

namespace {

// Unit face normals into fn; returns the unit vertex normals (the area-weighted sums of
// vertex_normals.h, normalised).
Eigen::MatrixX3d normals(const Eigen::MatrixX3d& P, const Eigen::MatrixX3i& T, Eigen::MatrixX3d& fn) {
  fn.resize(T.rows(), 3);
  for (int f = 0; f < T.rows(); ++f)
    fn.row(f) = (P.row(T(f, 1)) - P.row(T(f, 0))).cross(P.row(T(f, 2)) - P.row(T(f, 0))).normalized();
  const std::vector<Eigen::Vector3d> sum =
      vertex_area_vectors(T, size_t(P.rows()), [&](int f, int k) { return Eigen::Vector3d(P.row(T(f, k))); });
  Eigen::MatrixX3d vn(P.rows(), 3);
  for (size_t v = 0; v < sum.size(); ++v) vn.row(Eigen::Index(v)) = sum[v].transpose();
  vn.rowwise().normalize();
  return vn;
}

// Nodes that received no vertex take the nearest vertex of a node that owns several.
void give_every_node_a_vertex(const Eigen::MatrixX3d& V, const SkeletonGraph& g, std::vector<int>& owner) {
  std::vector<int> count(g.pos.size(), 0);
  for (int o : owner) ++count[o];
  for (size_t a = 0; a < g.pos.size(); ++a) {
    if (count[a] > 0) continue;
    int best = -1;
    double d = INFINITY;
    for (int i = 0; i < V.rows(); ++i) {
      const double e = (V.row(i).transpose() - g.pos[a]).squaredNorm();
      if (count[owner[i]] > 1 && e < d) d = e, best = i;
    }
    if (best < 0) continue;
    --count[owner[best]];
    owner[best] = int(a);
    ++count[a];
  }
}

}  // namespace

void make_proxy(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, int target_vertices, Eigen::MatrixX3d& XV,
                Eigen::MatrixX3i& XF, const TriangleBvh* surface) {
  double area = 0;
  for (int f = 0; f < F.rows(); ++f) area += triangle_area(V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2)));
  const int target = std::max(target_vertices, 4);
  const double len = equilateral_edge_length(area, target);
  std::vector<std::array<int, 3>> corners(size_t(F.rows()));
  for (int f = 0; f < F.rows(); ++f) corners[size_t(f)] = {F(f, 0), F(f, 1), F(f, 2)};
  Mesh m;
  if (V.rows() > kRenumberCopiesFrom && scattered_numbering(corners, size_t(V.rows()))) {
    MeshSoup soup;  // remeshed in spatial order (spatial_order.h)
    for (int i = 0; i < V.rows(); ++i) soup.points.push_back(V.row(i).transpose());
    soup.triangles = std::move(corners);
    m = build_mesh(spatially_ordered(soup));
  } else {
    m.reserve(size_t(V.rows()), size_t(F.rows()) * 3 / 2 + 3, size_t(F.rows()));
    for (int i = 0; i < V.rows(); ++i) m.add_vertex({V(i, 0), V(i, 1), V(i, 2)});
    add_faces_or_each(m, corners);  // add_face's connectivity, built faster (add_faces.h)
  }
  const TriangleBvh own = surface ? TriangleBvh() : TriangleBvh(V, F);
  const TriangleBvh& bvh = surface ? *surface : own;
  isotropic_remesh(m, len, 8, [&](const Eigen::Vector3d& p) { return bvh.closest_point(p).point; });
  XV = vertex_matrix(m);
  XF = face_matrix(m);
}

std::vector<int> map_to_nodes(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::MatrixX3d& XV,
                              const Eigen::MatrixX3i& XF, const SkeletonGraph& g) {
  Eigen::MatrixX3d fn, xfn;
  const Eigen::MatrixX3d vn = normals(V, F, fn), xvn = normals(XV, XF, xfn);
  std::vector<int> xnode(XV.rows(), -1);
  for (size_t a = 0; a < g.verts.size(); ++a)
    for (int v : g.verts[a]) xnode[v] = int(a);
  const TriangleBvh bvh(XV, XF);
  std::vector<int> owner(V.rows());
  for (int i = 0; i < V.rows(); ++i) {
    const Eigen::Vector3d p = V.row(i), n = vn.row(i);
    const auto c = bvh.closest_point(p);
    int best = -1;
    if (Eigen::Vector3d(xfn.row(c.face)).dot(n) > 0) {
      double d = INFINITY;
      for (int k = 0; k < 3; ++k) {
        const double e = (XV.row(XF(c.face, k)).transpose() - c.point).squaredNorm();
        if (e < d) d = e, best = XF(c.face, k);
      }
    } else {
      double d = INFINITY;
      for (int x = 0; x < XV.rows(); ++x) {
        const double e = (XV.row(x).transpose() - p).squaredNorm();
        if (Eigen::Vector3d(xvn.row(x)).dot(n) > 0 && e < d) d = e, best = x;
      }
      if (best < 0) best = XF(c.face, 0);
    }
    owner[i] = xnode[best];
  }
  give_every_node_a_vertex(V, g, owner);
  return owner;
}

}  // namespace sdm
