#include "libstm/mesh/mesh_geometry.h"

namespace sdm {

std::vector<double> vertex_areas(const Mesh& m, double factor) {
  std::vector<double> a(m.n_vertices(), 0.0);
  for (auto f : m.faces()) {
    const double x = m.calc_face_area(f) * factor / 3;
    for (auto v : m.fv_range(f)) a[v.idx()] += x;
  }
  return a;
}

Mesh with_planar_uv(const Mesh& m) {
  Mesh out = m;
  out.request_halfedge_texcoords2D();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (auto v : m.vertices()) lo = lo.cwiseMin(point(m, v)), hi = hi.cwiseMax(point(m, v));
  const Eigen::Vector3d ext = (hi - lo).cwiseMax(1e-300);
  int smallest = 0;
  ext.minCoeff(&smallest);
  const int a = (smallest + 1) % 3, b = (smallest + 2) % 3;
  for (auto h : out.halfedges()) {
    if (out.is_boundary(h)) continue;
    const Eigen::Vector3d p = point(out, out.to_vertex_handle(h));
    out.set_texcoord2D(h, Mesh::TexCoord2D(float((p[a] - lo[a]) / ext[a]), float((p[b] - lo[b]) / ext[b])));
  }
  return out;
}

}  // namespace sdm
