#include "libstm/mesh/mesh_geometry.h"

#include <cmath>
#include <functional>
#include <queue>

namespace sdm {

double surface_area(const Mesh& m) {
  double area = 0;
  for (auto f : m.faces()) area += m.calc_face_area(f);
  return area;
}

double longest_edge(const Mesh& m) {
  double longest = 0;
  for (auto e : m.edges()) longest = std::max(longest, double(m.calc_edge_length(e)));
  return longest;
}

std::vector<double> vertex_areas(const Mesh& m, double factor) {
  std::vector<double> a(m.n_vertices(), 0.0);
  for (auto f : m.faces()) {
    const double x = m.calc_face_area(f) * factor / 3;
    for (auto v : m.fv_range(f)) a[v.idx()] += x;
  }
  return a;
}

std::vector<double> edge_path_distances(const Mesh& m, int from) {
  std::vector<double> d(m.n_vertices(), INFINITY);
  if (from < 0 || from >= int(m.n_vertices())) return d;
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  d[from] = 0, queue.push({0.0, from});
  while (!queue.empty()) {
    const auto [dist, v] = queue.top();
    queue.pop();
    if (dist > d[v]) continue;
    const Mesh::VertexHandle vh = m.vertex_handle(v);
    for (auto w : m.vv_range(vh)) {
      const double nd = dist + (point(m, w) - point(m, vh)).norm();
      if (nd < d[w.idx()]) d[w.idx()] = nd, queue.push({nd, w.idx()});
    }
  }
  return d;
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
