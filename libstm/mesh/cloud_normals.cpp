// Normals of a point cloud (point_cloud.h): principal axes of neighbourhoods, oriented along a
// minimum spanning tree (Hoppe et al. 1992, "Surface reconstruction from unorganized points").
#include "libstm/core/parallel.h"
#include "libstm/geometry/point_kdtree.h"
#include "libstm/mesh/point_cloud.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace sdm {
namespace {

// A graph's adjacency in one array: the neighbours of v are adj[first[v], first[v + 1]).
struct Adjacency {
  std::vector<int> first, adj;
  int begin(int v) const { return first[size_t(v)]; }
  int end(int v) const { return first[size_t(v) + 1]; }
  int at(int e) const { return adj[size_t(e)]; }
};

// The undirected graph of `edges` (pairs of points), each list in the order the edges are given.
Adjacency adjacency(int n, const std::vector<std::pair<int, int>>& edges) {
  Adjacency g;
  g.first.assign(size_t(n) + 1, 0);
  for (const auto& [i, j] : edges) ++g.first[size_t(i) + 1], ++g.first[size_t(j) + 1];
  for (int i = 0; i < n; ++i) g.first[size_t(i) + 1] += g.first[size_t(i)];
  g.adj.resize(size_t(g.first[size_t(n)]));
  std::vector<int> fill(g.first.begin(), g.first.end() - 1);
  for (const auto& [i, j] : edges) g.adj[size_t(fill[size_t(i)]++)] = j, g.adj[size_t(fill[size_t(j)]++)] = i;
  return g;
}

// The minimum spanning forest of the kNN graph `edges` under the cost 1 - |n_i . n_j| (Kruskal:
// the edges by cost, then by their points; a union-find joins the parts). With distinct costs the
// forest is the only one, the one Prim's tree from any root grows. An edge given twice (each way)
// is met twice in a row, the second time within a part.
std::vector<std::pair<int, int>> spanning_forest(int n, const std::vector<std::pair<int, int>>& edges,
                                                  const std::vector<Eigen::Vector3d>& normal) {
  struct Edge {
    double cost;
    int a, b;
    bool operator<(const Edge& o) const { return cost != o.cost ? cost < o.cost : a != o.a ? a < o.a : b < o.b; }
  };
  std::vector<Edge> sorted(edges.size());
  for (size_t e = 0; e < edges.size(); ++e) {
    const auto [a, b] = std::minmax(edges[e].first, edges[e].second);
    sorted[e] = {1.0 - std::abs(normal[size_t(a)].dot(normal[size_t(b)])), a, b};
  }
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> parent(static_cast<size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int v) {
    while (parent[size_t(v)] != v) v = parent[size_t(v)] = parent[size_t(parent[size_t(v)])];
    return v;
  };
  std::vector<std::pair<int, int>> tree;
  tree.reserve(size_t(n));
  for (const Edge& e : sorted) {
    const int a = find(e.a), b = find(e.b);
    if (a == b) continue;
    parent[size_t(a)] = b;
    tree.push_back({e.a, e.b});
  }
  return tree;
}

}  // namespace

std::vector<Eigen::Vector3d> estimate_normals(const std::vector<Eigen::Vector3d>& points, int k) {
  const int n = int(points.size());
  const PointKdTree tree(points);
  std::vector<Eigen::Vector3d> normal(points.size(), Eigen::Vector3d::UnitZ());
  // Each point's k + 1 nearest (itself among them) side by side: near[i * kn, i * kn + count[i]).
  const int kn = std::max(1, k + 1);
  std::vector<int> near(size_t(n) * size_t(kn)), count(size_t(n), 0);
  parallel_for(n, 512, [&](int i) {
    int* own = near.data() + size_t(i) * size_t(kn);
    std::vector<double> d2(static_cast<size_t>(kn));
    const int m = count[size_t(i)] = tree.nearest(points[size_t(i)], kn, own, d2.data());
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int a = 0; a < m; ++a) mean += points[size_t(own[a])];
    mean /= double(m);
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (int a = 0; a < m; ++a) cov += (points[size_t(own[a])] - mean) * (points[size_t(own[a])] - mean).transpose();
    normal[size_t(i)] = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(0);
  });
  // The kNN graph, both ways: the flood below meets each list in the order i ascending, then i's
  // neighbours nearest first.
  std::vector<std::pair<int, int>> edges;
  edges.reserve(near.size());
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < count[size_t(i)]; ++a)
      if (const int j = near[size_t(i) * size_t(kn) + size_t(a)]; j != i) edges.push_back({i, j});
  const Adjacency graph = adjacency(n, edges);
  const Adjacency forest = adjacency(n, spanning_forest(n, edges, normal));
  // From the highest point of each part (its normal turned up) along the forest, each normal turned
  // to agree with its parent's; the cost 1 - |n_i . n_j| walks along flat regions first.
  std::vector<int> part(size_t(n), -1);
  std::vector<char> oriented(size_t(n), 0);
  int parts = 0;
  for (int start = 0; start < n; ++start) {
    if (part[size_t(start)] >= 0) continue;
    int root = start;  // the part's highest point: found by a flood from start
    std::vector<int> flood{start}, members;
    part[size_t(start)] = parts;
    while (!flood.empty()) {
      const int v = flood.back();
      flood.pop_back();
      members.push_back(v);
      if (points[size_t(v)].z() > points[size_t(root)].z()) root = v;
      for (int e = graph.begin(v); e < graph.end(v); ++e)
        if (const int w = graph.at(e); part[size_t(w)] < 0) part[size_t(w)] = parts, flood.push_back(w);
    }
    ++parts;
    if (normal[size_t(root)].z() < 0) normal[size_t(root)] = -normal[size_t(root)];
    std::vector<int> walk{root};
    oriented[size_t(root)] = 1;
    while (!walk.empty()) {
      const int v = walk.back();
      walk.pop_back();
      for (int e = forest.begin(v); e < forest.end(v); ++e) {
        const int w = forest.at(e);
        if (oriented[size_t(w)]) continue;
        oriented[size_t(w)] = 1;
        if (normal[size_t(w)].dot(normal[size_t(v)]) < 0) normal[size_t(w)] = -normal[size_t(w)];
        walk.push_back(w);
      }
    }
    // The part as a whole faces away from its centroid.
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int v : members) centroid += points[size_t(v)];
    centroid /= double(members.size());
    double out = 0;
    for (int v : members) out += normal[size_t(v)].dot(points[size_t(v)] - centroid);
    if (out < 0)
      for (int v : members) normal[size_t(v)] = -normal[size_t(v)];
  }
  return normal;
}

}  // namespace sdm
