#include "libstm/correspondence/end_distances.h"

#include "libstm/core/errors.h"
#include "libstm/mesh/mesh_geometry.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>

namespace sdm {

namespace {

// Per end node of the shared graph, the vertices it owns on the mesh of `sk` (empty where none).
std::vector<std::vector<int>> end_vertices(const Skeleton& sk, const std::vector<int>& ends) {
  std::vector<int> slot(sk.nodes.size(), -1);
  for (size_t e = 0; e < ends.size(); ++e) slot[size_t(ends[e])] = int(e);
  std::vector<std::vector<int>> out(ends.size());
  for (size_t v = 0; v < sk.vertex_node.size(); ++v) {
    const int n = sk.vertex_node[v];
    if (n >= 0 && n < int(slot.size()) && slot[size_t(n)] >= 0) out[size_t(slot[size_t(n)])].push_back(int(v));
  }
  return out;
}

}  // namespace

std::vector<double> unit_area_distances(const Mesh& mesh, const std::vector<int>& sources) {
  std::vector<double> d(mesh.n_vertices(), INFINITY);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (int s : sources) {
    if (s < 0 || s >= int(d.size())) throw InputError("unit_area_distances: vertex " + std::to_string(s) + " is not on the mesh");
    d[size_t(s)] = 0, queue.emplace(0.0, s);
  }
  while (!queue.empty()) {
    const auto [dist, v] = queue.top();
    queue.pop();
    if (dist > d[size_t(v)]) continue;
    const auto vh = mesh.vertex_handle(v);
    const Eigen::Vector3d p = point(mesh, vh);
    for (auto w : mesh.vv_range(vh)) {
      const double nd = dist + (point(mesh, w) - p).norm();
      if (nd < d[size_t(w.idx())]) d[size_t(w.idx())] = nd, queue.emplace(nd, w.idx());
    }
  }
  const double scale = 1 / std::sqrt(std::max(surface_area(mesh), 1e-300));
  for (double& x : d) x *= scale;
  return d;
}

ZoomOutFeatures end_distances(const Mesh& source, const Mesh& target, const SharedSkeletons& sk) {
  if (sk.a.vertex_node.size() != source.n_vertices() || sk.b.vertex_node.size() != target.n_vertices())
    throw InputError("end_distances: the shared skeletons' vertex_node does not cover the meshes");
  const std::vector<int> da = sk.a.degrees(), db = sk.b.degrees();
  std::vector<int> ends;
  for (size_t n = 0; n < da.size() && n < db.size(); ++n)
    if (da[n] == 1 && db[n] == 1) ends.push_back(int(n));
  const std::vector<std::vector<int>> on_a = end_vertices(sk.a, ends), on_b = end_vertices(sk.b, ends);
  std::vector<std::vector<double>> cols_a, cols_b;
  for (size_t e = 0; e < ends.size(); ++e) {
    if (on_a[e].empty() || on_b[e].empty()) continue;
    cols_a.push_back(unit_area_distances(source, on_a[e])), cols_b.push_back(unit_area_distances(target, on_b[e]));
  }
  auto matrix = [](const std::vector<std::vector<double>>& cols, size_t rows) {
    Eigen::MatrixXd m(Eigen::Index(rows), Eigen::Index(cols.size()));
    for (size_t c = 0; c < cols.size(); ++c) {
      double top = 0;
      for (double x : cols[c])
        if (std::isfinite(x)) top = std::max(top, x);
      for (size_t r = 0; r < rows; ++r) m(Eigen::Index(r), Eigen::Index(c)) = std::isfinite(cols[c][r]) ? cols[c][r] : top;
    }
    return m;
  };
  return {matrix(cols_a, source.n_vertices()), matrix(cols_b, target.n_vertices())};
}

}  // namespace sdm
