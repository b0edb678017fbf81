// Normals of a point cloud (point_cloud.h): principal axes of neighbourhoods, oriented along a
// minimum spanning tree (Hoppe et al. 1992, "Surface reconstruction from unorganized points").
#include "libstm/core/parallel.h"
#include "libstm/geometry/point_kdtree.h"
#include "libstm/mesh/point_cloud.h"

#include <algorithm>
#include <queue>

namespace sdm {

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
  // The kNN graph, both ways, in one array: adj[first[v], first[v + 1]) (each list in the order
  // the pairs are met: i ascending, then i's neighbours nearest first).
  std::vector<int> first(size_t(n) + 1, 0);
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < count[size_t(i)]; ++a)
      if (const int j = near[size_t(i) * size_t(kn) + size_t(a)]; j != i) ++first[size_t(i) + 1], ++first[size_t(j) + 1];
  for (int i = 0; i < n; ++i) first[size_t(i) + 1] += first[size_t(i)];
  std::vector<int> adj(static_cast<size_t>(first[size_t(n)])), fill(first.begin(), first.end() - 1);
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < count[size_t(i)]; ++a)
      if (const int j = near[size_t(i) * size_t(kn) + size_t(a)]; j != i) adj[size_t(fill[size_t(i)]++)] = j, adj[size_t(fill[size_t(j)]++)] = i;
  // Prim's tree from the highest point of each part (its normal turned up), each normal turned to
  // agree with its parent's; the cost 1 - |n_i . n_j| walks along flat regions first.
  std::vector<char> done(size_t(n), 0);
  std::vector<int> part(size_t(n), -1);
  std::vector<int> roots;
  using Item = std::pair<double, std::pair<int, int>>;  // cost, (point, parent)
  for (int start = 0; start < n; ++start) {
    if (done[size_t(start)]) continue;
    int root = start;  // the part's highest point: found by a flood from start
    std::vector<int> flood{start}, members;
    part[size_t(start)] = int(roots.size());
    while (!flood.empty()) {
      const int v = flood.back();
      flood.pop_back();
      members.push_back(v);
      if (points[size_t(v)].z() > points[size_t(root)].z()) root = v;
      for (int e = first[size_t(v)]; e < first[size_t(v) + 1]; ++e)
        if (const int w = adj[size_t(e)]; part[size_t(w)] < 0) part[size_t(w)] = int(roots.size()), flood.push_back(w);
    }
    roots.push_back(root);
    if (normal[size_t(root)].z() < 0) normal[size_t(root)] = -normal[size_t(root)];
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    heap.push({0.0, {root, root}});
    while (!heap.empty()) {
      const auto [v, parent] = heap.top().second;
      heap.pop();
      if (done[size_t(v)]) continue;
      done[size_t(v)] = 1;
      if (normal[size_t(v)].dot(normal[size_t(parent)]) < 0) normal[size_t(v)] = -normal[size_t(v)];
      for (int e = first[size_t(v)]; e < first[size_t(v) + 1]; ++e)
        if (const int w = adj[size_t(e)]; !done[size_t(w)]) heap.push({1.0 - std::abs(normal[size_t(v)].dot(normal[size_t(w)])), {w, v}});
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
