#pragma once
/// The skeleton of one connected part while it is being built: what connectivity surgery
/// (surgery.h) hands to refinement (refine_skeleton.h) and candidate choice (choose_candidate.h).
/// Nodes own clusters of the part's vertices (part-local indices); extract_skeleton turns the chosen
/// graph into the Skeleton of the whole mesh.
#include <Eigen/Dense>

#include <algorithm>
#include <set>
#include <utility>
#include <vector>

namespace sdm {

struct SkeletonGraph {
  std::vector<Eigen::Vector3d> pos;       ///< node position
  std::vector<Eigen::Vector3d> fallback;  ///< contracted position, used when pos must be pulled in
  std::vector<std::vector<int>> verts;    ///< original (part-local) vertices per node
  std::set<std::pair<int, int>> edges;    ///< (a, b) with a < b

  /// Number of edges at each node.
  std::vector<int> degrees() const {
    std::vector<int> deg(pos.size(), 0);
    for (const auto& e : edges) ++deg[e.first], ++deg[e.second];
    return deg;
  }
  /// Nodes of degree 1.
  int ends() const {
    const std::vector<int> deg = degrees();
    return int(std::count(deg.begin(), deg.end(), 1));
  }
  /// Node -> neighbouring nodes, each list ascending.
  std::vector<std::vector<int>> adjacency() const {
    std::vector<std::vector<int>> adj(pos.size());
    for (const auto& e : edges) adj[e.first].push_back(e.second), adj[e.second].push_back(e.first);
    return adj;
  }
};

/// The graph without the nodes where `keep` is 0; the others keep their order and data. `edges`
/// (in g's numbering, both ends kept) become the result's edges. The kept vertex lists are moved
/// out of g.
inline SkeletonGraph keep_nodes(SkeletonGraph& g, const std::vector<char>& keep, const std::set<std::pair<int, int>>& edges) {
  SkeletonGraph out;
  std::vector<int> id(g.pos.size(), -1);
  for (size_t a = 0; a < g.pos.size(); ++a)
    if (keep[a]) {
      id[a] = int(out.pos.size());
      out.pos.push_back(g.pos[a]);
      out.fallback.push_back(g.fallback[a]);
      out.verts.push_back(std::move(g.verts[a]));
    }
  for (const auto& e : edges) out.edges.insert({id[e.first], id[e.second]});
  return out;
}

/// Sorted vectors as small sets (the neighbour lists of surgery and refinement).
inline void insert_sorted(std::vector<int>& v, int x) {
  auto it = std::lower_bound(v.begin(), v.end(), x);
  if (it == v.end() || *it != x) v.insert(it, x);
}
inline void erase_sorted(std::vector<int>& v, int x) {
  auto it = std::lower_bound(v.begin(), v.end(), x);
  if (it != v.end() && *it == x) v.erase(it);
}

}  // namespace sdm
