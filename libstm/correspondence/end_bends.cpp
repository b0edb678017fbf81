#include "libstm/correspondence/end_bends.h"

#include "libstm/geometry/differential_geometry.h"

#include <algorithm>
#include <stdexcept>

namespace sdm {

namespace {

// The point at arc length s along the polyline nodes[path] (clamped to its ends).
Eigen::Vector3d at_length(const std::vector<Eigen::Vector3d>& nodes, const std::vector<int>& path, double s) {
  for (size_t i = 0; i + 1 < path.size(); ++i) {
    const Eigen::Vector3d &p = nodes[size_t(path[i])], &q = nodes[size_t(path[i + 1])];
    const double len = (q - p).norm();
    if (s <= len && len > 0) return p + (s / len) * (q - p);
    s -= len;
  }
  return nodes[size_t(path.back())];
}

double length(const std::vector<Eigen::Vector3d>& nodes, const std::vector<int>& path) {
  double total = 0;
  for (size_t i = 0; i + 1 < path.size(); ++i) total += (nodes[size_t(path[i + 1])] - nodes[size_t(path[i])]).norm();
  return total;
}

// Per end node, its chain: the nodes from it to the first node whose degree is not 2.
std::vector<std::vector<int>> end_chains(const Skeleton& s) {
  const std::vector<std::vector<int>> adj = s.adjacency();
  std::vector<std::vector<int>> chains;
  for (size_t e = 0; e < adj.size(); ++e) {
    if (adj[e].size() != 1) continue;
    std::vector<int> path{int(e)};
    int prev = -1, cur = int(e);
    while (path.size() <= adj.size()) {
      const auto& nb = adj[size_t(cur)];
      const int next = nb[0] != prev ? nb[0] : (nb.size() > 1 ? nb[1] : -1);
      if (next < 0) break;
      prev = cur, cur = next;
      path.push_back(cur);
      if (adj[size_t(cur)].size() != 2) break;
    }
    chains.push_back(std::move(path));
  }
  return chains;
}

}  // namespace

Eigen::Vector3d end_bend(const std::vector<Eigen::Vector3d>& nodes, const std::vector<int>& path) {
  const double total = length(nodes, path);
  if (path.size() < 2 || !(total > 0)) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d end = nodes[size_t(path.front())], tip = at_length(nodes, path, 0.15 * total),
                        base = at_length(nodes, path, 0.45 * total);
  const Eigen::Vector3d last = end - tip, before = tip - base;
  if (!(last.norm() > 0) || !(before.norm() > 0)) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d d = last.normalized(), axis = before.normalized();
  return d - d.dot(axis) * axis;
}

double end_bend_agreement(const Skeleton& a, const Skeleton& b) {
  if (a.nodes.size() != b.nodes.size() || a.edges != b.edges)
    throw std::invalid_argument("end_bend_agreement: the skeletons do not share one graph");
  const std::vector<std::vector<int>> chains = end_chains(a);
  if (chains.size() < 3) return 0;
  std::vector<Eigen::Vector3d> core_a, core_b;
  for (const auto& path : chains) {
    core_a.push_back(a.nodes[size_t(path.back())]), core_b.push_back(b.nodes[size_t(path.back())]);
    core_a.push_back(at_length(a.nodes, path, 0.85 * length(a.nodes, path)));
    core_b.push_back(at_length(b.nodes, path, 0.85 * length(b.nodes, path)));
  }
  const Eigen::Matrix3d R = fit_similarity(core_a, core_b, std::vector<double>(core_a.size(), 1.0)).rotation;
  double agreement = 0;
  for (const auto& path : chains) agreement += (R * end_bend(a.nodes, path)).dot(end_bend(b.nodes, path));
  return agreement;
}

}  // namespace sdm
