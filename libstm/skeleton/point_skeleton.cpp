#include "libstm/skeleton/point_skeleton.h"

#include "libstm/core/stopwatch.h"
#include "libstm/core/union_find.h"
#include "libstm/geometry/point_kdtree.h"
#include "libstm/skeleton/skeleton_graph.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <queue>

namespace sdm {

namespace {

// A cloud's spacing for the skeleton's scales: the mean distance from a point to its nearest
// other point, over about 2000 of them.
double sampled_spacing(const std::vector<Eigen::Vector3d>& points, const PointKdTree& tree) {
  return mean_nearest_distance(points, tree, std::max(1, int(points.size()) / 2000));
}

// An even subsample of about `target` points: greedy covering by balls in file order, the radius
// from the mean `spacing` (a surface's sample count falls with the square of the spacing).
std::vector<int> even_subsample(const std::vector<Eigen::Vector3d>& points, int target, const PointKdTree& tree, double spacing) {
  const int n = int(points.size());
  double r = spacing * std::sqrt(double(n) / target);
  std::vector<int> samples;
  for (int attempt = 0; attempt < 4; ++attempt) {
    samples.clear();
    std::vector<char> covered(size_t(n), 0);
    for (int i = 0; i < n; ++i) {
      if (covered[size_t(i)]) continue;
      samples.push_back(i);
      for (int j : tree.within(points[size_t(i)], r)) covered[size_t(j)] = 1;
    }
    if (samples.size() <= size_t(1.25 * target)) break;
    r *= std::sqrt(double(samples.size()) / target);
  }
  return samples;
}

// Farthest-point sampling of the contracted points C until every point is within `r` of a node:
// the node of every point (its nearest) and the node count.
int farthest_point_nodes(const Eigen::MatrixX3d& C, double r, std::vector<int>& node_of) {
  const int m = int(C.rows());
  const Eigen::RowVector3d centre = C.colwise().mean();
  int first = 0;
  (C.rowwise() - centre).rowwise().squaredNorm().maxCoeff(&first);
  std::vector<double> d(size_t(m), std::numeric_limits<double>::infinity());
  node_of.assign(size_t(m), 0);
  int nodes = 0;
  for (int next = first;;) {
    for (int i = 0; i < m; ++i) {
      const double di = (C.row(i) - C.row(next)).squaredNorm();
      if (di < d[size_t(i)]) d[size_t(i)] = di, node_of[size_t(i)] = nodes;
    }
    ++nodes;
    next = int(std::max_element(d.begin(), d.end()) - d.begin());
    if (d[size_t(next)] <= r * r) break;
  }
  return nodes;
}

// The graph of `groups` (per sample, its node id, ids 0..count-1): node positions the centroids of
// their samples' contracted points, edges where a ring joins two nodes.
SkeletonGraph graph_of(const std::vector<int>& group, int count, const Eigen::MatrixX3d& C, const std::vector<std::vector<int>>& rings) {
  SkeletonGraph g;
  g.pos.assign(size_t(count), Eigen::Vector3d::Zero());
  g.verts.resize(size_t(count));
  for (int i = 0; i < int(group.size()); ++i) g.verts[size_t(group[size_t(i)])].push_back(i), g.pos[size_t(group[size_t(i)])] += C.row(i).transpose();
  for (int a = 0; a < count; ++a) g.pos[size_t(a)] /= double(std::max<size_t>(g.verts[size_t(a)].size(), 1));
  g.fallback = g.pos;
  for (int i = 0; i < int(group.size()); ++i)
    for (int j : rings[size_t(i)]) {
      const int a = group[size_t(i)], b = group[size_t(j)];
      if (a != b) g.edges.insert({std::min(a, b), std::max(a, b)});
    }
  return g;
}

// The graph with the nodes of each union-find set merged (renumbered in order of their first node):
// positions the centroids of the merged clusters' contracted points, the edges between sets kept.
SkeletonGraph merged(const SkeletonGraph& g, UnionFind& sets, const Eigen::MatrixX3d& C) {
  std::vector<int> id(g.pos.size(), -1);
  int count = 0;
  for (size_t a = 0; a < g.pos.size(); ++a) {
    const int root = sets.find(int(a));
    if (id[size_t(root)] < 0) id[size_t(root)] = count++;
    id[a] = id[size_t(root)];
  }
  SkeletonGraph out;
  out.pos.assign(size_t(count), Eigen::Vector3d::Zero());
  out.verts.resize(size_t(count));
  for (size_t a = 0; a < g.pos.size(); ++a)
    for (int v : g.verts[a]) out.verts[size_t(id[a])].push_back(v), out.pos[size_t(id[a])] += C.row(v).transpose();
  for (int a = 0; a < count; ++a) out.pos[size_t(a)] /= double(std::max<size_t>(out.verts[size_t(a)].size(), 1));
  out.fallback = out.pos;
  for (const auto& [a, b] : g.edges)
    if (id[size_t(a)] != id[size_t(b)]) out.edges.insert({std::min(id[size_t(a)], id[size_t(b)]), std::max(id[size_t(a)], id[size_t(b)])});
  return out;
}

// Collapses the shortest edge of every triangle (Cao et al., section 5), pass after pass.
int collapse_triangles(SkeletonGraph& g, const Eigen::MatrixX3d& C) {
  int collapsed = 0;
  for (;;) {
    const auto adj = g.adjacency();
    UnionFind sets(int(g.pos.size()));
    std::vector<char> touched(g.pos.size(), 0);
    int pass = 0;
    for (const auto& [a, b] : g.edges) {
      if (touched[size_t(a)] || touched[size_t(b)]) continue;
      for (int c : adj[size_t(a)]) {
        if (c == b || touched[size_t(c)] || !std::binary_search(adj[size_t(b)].begin(), adj[size_t(b)].end(), c)) continue;
        const double ab = (g.pos[size_t(a)] - g.pos[size_t(b)]).norm(), bc = (g.pos[size_t(b)] - g.pos[size_t(c)]).norm(),
                     ca = (g.pos[size_t(c)] - g.pos[size_t(a)]).norm();
        const int u = ab <= bc && ab <= ca ? a : bc <= ca ? b : c, v = ab <= bc && ab <= ca ? b : bc <= ca ? c : a;
        sets.unite(u, v);
        touched[size_t(a)] = touched[size_t(b)] = touched[size_t(c)] = 1;
        ++pass;
        break;
      }
    }
    if (pass == 0) return collapsed;
    collapsed += pass;
    g = merged(g, sets, C);
  }
}

// Per node, the mean distance from its samples' points to the node.
std::vector<double> cluster_radii(const SkeletonGraph& g, const std::vector<Eigen::Vector3d>& points, const std::vector<int>& samples) {
  std::vector<double> r(g.pos.size(), 0.0);
  for (size_t a = 0; a < g.pos.size(); ++a) {
    for (int v : g.verts[a]) r[a] += (points[size_t(samples[size_t(v)])] - g.pos[a]).norm();
    r[a] /= double(std::max<size_t>(g.verts[a].size(), 1));
  }
  return r;
}

// Per node, the centroid of its samples' points (not of their contracted places: the contraction
// draws a fat ring towards its hole).
std::vector<Eigen::Vector3d> point_centres(const SkeletonGraph& g, const std::vector<Eigen::Vector3d>& points, const std::vector<int>& samples) {
  std::vector<Eigen::Vector3d> c(g.pos.size(), Eigen::Vector3d::Zero());
  for (size_t a = 0; a < g.pos.size(); ++a) {
    for (int v : g.verts[a]) c[a] += points[size_t(samples[size_t(v)])];
    c[a] /= double(std::max<size_t>(g.verts[a].size(), 1));
  }
  return c;
}

// Per node, the mean distance from its samples' points to the nearest of its edges drawn between
// `centre`s (to its centre when it has none): the radius of the tube around the graph.
std::vector<double> tube_radii(const SkeletonGraph& g, const std::vector<Eigen::Vector3d>& centre, const std::vector<Eigen::Vector3d>& points,
                               const std::vector<int>& samples) {
  const auto adj = g.adjacency();
  std::vector<double> r(g.pos.size(), 0.0);
  for (size_t a = 0; a < g.pos.size(); ++a) {
    for (int v : g.verts[a]) {
      const Eigen::Vector3d p = points[size_t(samples[size_t(v)])] - centre[a];
      double best = p.norm();
      for (int b : adj[a]) {
        const Eigen::Vector3d u = centre[size_t(b)] - centre[a];
        const double t = std::clamp(p.dot(u) / std::max(u.squaredNorm(), 1e-300), 0.0, 1.0);
        best = std::min(best, (p - t * u).norm());
      }
      r[a] += best;
    }
    r[a] /= double(std::max<size_t>(g.verts[a].size(), 1));
  }
  return r;
}

// Shortest path length from a to b over `adj` (infinity when none), and the nodes on it.
double shortest_path(const SkeletonGraph& g, const std::vector<std::vector<int>>& adj, int a, int b, std::vector<int>& path) {
  std::vector<double> dist(g.pos.size(), std::numeric_limits<double>::infinity());
  std::vector<int> from(g.pos.size(), -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
  dist[size_t(a)] = 0, heap.push({0.0, a});
  while (!heap.empty()) {
    const auto [d, v] = heap.top();
    heap.pop();
    if (d > dist[size_t(v)]) continue;
    if (v == b) break;
    for (int w : adj[size_t(v)]) {
      const double nd = d + (g.pos[size_t(v)] - g.pos[size_t(w)]).norm();
      if (nd < dist[size_t(w)]) dist[size_t(w)] = nd, from[size_t(w)] = v, heap.push({nd, w});
    }
  }
  path.clear();
  for (int v = b; v >= 0 && std::isfinite(dist[size_t(b)]); v = from[size_t(v)]) path.push_back(v);
  return dist[size_t(b)];
}

// Whether the disc a cycle spans (the fan from the mean of its points `ring` to them) passes
// within `near` of a point away from its rim: a hole's cycle runs around the hole, so its disc
// crosses the hole's wall; a cycle around a tube, or in the web a flat part contracts into, spans
// the inside of the volume, away from every point.
bool spans_wall(const std::vector<Eigen::Vector3d>& ring, const PointKdTree& tree, double near) {
  Eigen::Vector3d o = Eigen::Vector3d::Zero();
  for (const auto& p : ring) o += p / double(ring.size());
  for (size_t k = 0; k < ring.size(); ++k) {
    const Eigen::Vector3d& a = ring[k];
    const Eigen::Vector3d& b = ring[(k + 1) % ring.size()];
    const int across = std::max(1, int(std::ceil((b - a).norm() / near))), out = std::max(1, int(std::ceil((a - o).norm() / near)));
    for (int i = 0; i <= across; ++i)
      for (int j = out / 10 + 1; j < out - out / 5; ++j) {
        const Eigen::Vector3d x = o + double(j) / out * (a + double(i) / across * (b - a) - o);
        double d2 = 0;
        if (tree.nearest_one(x, &d2) >= 0 && d2 < near * near) return true;
      }
  }
  return false;
}

// Keeps a spanning forest (shortest edges first) and, of the other edges, those closing a cycle
// around a hole wider than the tube around it: longer than 2 pi times the mean radius of its
// nodes at the contracted places (the clusters' centroids); or, where the contraction drew a fat
// ring towards its hole (a torus whose hole is narrower than its tube), measured at the centroids
// of the nodes' points, when the cycle's disc crosses the points (spans_wall) and the ring of
// centroids is wider than 1.5 tube radii: the centroid of a torus's section (points uniform by
// area) lies r^2 / 2R outside its core circle of radius R, at 1.5 r when the hole closes (R = r).
int keep_wide_cycles(SkeletonGraph& g, const std::vector<Eigen::Vector3d>& points, const std::vector<int>& samples, const PointKdTree& tree,
                     double spacing) {
  const std::vector<double> radius = cluster_radii(g, points, samples);
  const std::vector<Eigen::Vector3d> centre = point_centres(g, points, samples);
  const std::vector<double> tube = tube_radii(g, centre, points, samples);
  std::vector<std::pair<int, int>> edges(g.edges.begin(), g.edges.end());
  auto length = [&](const std::pair<int, int>& e) { return (g.pos[size_t(e.first)] - g.pos[size_t(e.second)]).norm(); };
  std::stable_sort(edges.begin(), edges.end(), [&](const auto& x, const auto& y) { return length(x) < length(y); });
  UnionFind sets(int(g.pos.size()));
  std::set<std::pair<int, int>> kept;
  std::vector<std::pair<int, int>> rest;
  for (const auto& e : edges)
    if (sets.find(e.first) != sets.find(e.second)) sets.unite(e.first, e.second), kept.insert(e);
    else rest.push_back(e);
  std::vector<std::vector<int>> adj(g.pos.size());
  for (const auto& [a, b] : kept) adj[size_t(a)].push_back(b), adj[size_t(b)].push_back(a);
  int dropped = 0;
  std::vector<int> path;
  for (const auto& [a, b] : rest) {
    const double around = shortest_path(g, adj, a, b, path) + length({a, b});
    double r = 0, r_points = 0, around_points = (centre[size_t(a)] - centre[size_t(b)]).norm();
    std::vector<Eigen::Vector3d> ring;
    for (size_t k = 0; k < path.size(); ++k) {
      r += radius[size_t(path[k])], r_points += tube[size_t(path[k])], ring.push_back(centre[size_t(path[k])]);
      if (k > 0) around_points += (centre[size_t(path[k])] - centre[size_t(path[k - 1])]).norm();
    }
    r /= double(std::max<size_t>(path.size(), 1)), r_points /= double(std::max<size_t>(path.size(), 1));
    const bool wide = around > 2 * M_PI * r || (around_points > 3 * M_PI * r_points && spans_wall(ring, tree, 2 * spacing));
    if (wide) kept.insert({a, b}), adj[size_t(a)].push_back(b), adj[size_t(b)].push_back(a);
    else ++dropped;
  }
  g.edges = kept;
  return dropped;
}

// End branches shorter than prune_radius times their junction's radius (bumps of its section, or
// what the contraction left of a flat part) are merged into the junction, pass after pass.
int prune_short_branches(SkeletonGraph& g, const Eigen::MatrixX3d& C, const std::vector<Eigen::Vector3d>& points,
                         const std::vector<int>& samples, double prune_radius) {
  int pruned = 0;
  for (;;) {
    const std::vector<double> radius = cluster_radii(g, points, samples);
    const auto adj = g.adjacency();
    const std::vector<int> deg = g.degrees();
    UnionFind sets(int(g.pos.size()));
    std::vector<char> junction_used(g.pos.size(), 0);
    int pass = 0;
    for (int e = 0; e < int(g.pos.size()); ++e) {
      if (deg[size_t(e)] != 1) continue;
      std::vector<int> chain{e};
      double length = 0;
      int prev = e, cur = adj[size_t(e)][0];
      for (;;) {
        length += (g.pos[size_t(prev)] - g.pos[size_t(cur)]).norm();
        if (deg[size_t(cur)] != 2) break;
        chain.push_back(cur);
        const int next = adj[size_t(cur)][0] == prev ? adj[size_t(cur)][1] : adj[size_t(cur)][0];
        prev = cur, cur = next;
      }
      if (deg[size_t(cur)] < 3 || junction_used[size_t(cur)] || !(length < prune_radius * radius[size_t(cur)])) continue;
      junction_used[size_t(cur)] = 1;
      for (int v : chain) sets.unite(cur, v);
      ++pass;
    }
    if (pass == 0) return pruned;
    pruned += pass;
    g = merged(g, sets, C);
  }
}

// Each node at the centre of the points it owns, as the mesh path's refinement places them (the
// contraction also shortens curves: a torus's ring shrank by a fifth). The clusters the sampling
// of the contracted points leaves are cut obliquely across a tube, so their centres sat off its
// axis (by 0.06 of the radius on a capsule); each point first moves to the nearest of its node and
// that node's neighbours at their contracted places (on the axis; never leaving a node empty),
// which turns the clusters into slices across the tube. Once only: repeated with the centres, a
// node off the axis takes more points on its side, and the centres ran off to 0.6 of the radius.
void place_nodes(Skeleton& sk, const std::vector<Eigen::Vector3d>& points) {
  const auto adj = sk.adjacency();
  std::vector<int> owned(sk.nodes.size(), 0);
  for (int a : sk.vertex_node) ++owned[size_t(a)];
  for (size_t i = 0; i < points.size(); ++i) {
    int& a = sk.vertex_node[i];
    int best = a;
    for (int b : adj[size_t(a)])
      if ((points[i] - sk.nodes[size_t(b)]).squaredNorm() < (points[i] - sk.nodes[size_t(best)]).squaredNorm()) best = b;
    if (best != a && owned[size_t(a)] > 1) --owned[size_t(a)], ++owned[size_t(best)], a = best;
  }
  std::vector<Eigen::Vector3d> sum(sk.nodes.size(), Eigen::Vector3d::Zero());
  for (size_t i = 0; i < points.size(); ++i) sum[size_t(sk.vertex_node[i])] += points[i];
  for (size_t a = 0; a < sum.size(); ++a)
    if (owned[a] > 0) sk.nodes[a] = sum[a] / double(owned[a]);
  // A centre of a few hundred scan points is off the axis by the sampling's noise; along a branch
  // (nodes of degree 2) two passes of (previous + 2 self + next) / 4 average it out.
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<Eigen::Vector3d> next = sk.nodes;
    for (size_t a = 0; a < next.size(); ++a)
      if (adj[a].size() == 2) next[a] = 0.25 * (sk.nodes[size_t(adj[a][0])] + 2 * sk.nodes[a] + sk.nodes[size_t(adj[a][1])]);
    sk.nodes = std::move(next);
  }
}

}  // namespace

Skeleton point_cloud_skeleton(const std::vector<Eigen::Vector3d>& points, const PointSkeletonOptions& opt, const Progress& progress,
                              PointSkeletonStats* stats) {
  Stopwatch total, clock;
  PointSkeletonStats st;
  const int n = int(points.size());
  const PointKdTree tree(points);
  const double spacing = sampled_spacing(points, tree);
  std::vector<int> samples;
  if (opt.max_samples > 0 && n > opt.max_samples) samples = even_subsample(points, opt.max_samples, tree, spacing);
  else for (int i = 0; i < n; ++i) samples.push_back(i);
  std::vector<Eigen::Vector3d> sampled;
  for (int i : samples) sampled.push_back(points[size_t(i)]);
  st.samples = int(samples.size());
  if (progress && st.samples < n) progress("contracting an even subsample of " + std::to_string(st.samples) + " of the " + std::to_string(n) + " points");
  const PointContractResult cr = contract_points(sampled, opt.contraction, opt.solver, progress);
  st.iterations = cr.iterations;
  if (!cr.area_ratio.empty()) st.area_ratio = cr.area_ratio.back();
  st.contraction_seconds = clock.lap();
  Eigen::Vector3d lo = points[0], hi = points[0];
  for (const auto& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  std::vector<int> node_of;
  const int count = farthest_point_nodes(cr.positions, opt.node_spacing * (hi - lo).norm(), node_of);
  st.sampled_nodes = count;
  SkeletonGraph g = graph_of(node_of, count, cr.positions, cr.rings);
  st.sampling_seconds = clock.lap();
  st.collapsed_triangles = collapse_triangles(g, cr.positions);
  st.dropped_cycles = keep_wide_cycles(g, points, samples, tree, spacing);
  st.pruned_branches = prune_short_branches(g, cr.positions, points, samples, opt.prune_radius);
  st.graph_seconds = clock.lap();
  Skeleton sk;
  sk.nodes = g.pos;
  for (const auto& [a, b] : g.edges) sk.edges.push_back({a, b});
  std::vector<int> node_of_sample(samples.size(), 0);
  for (size_t a = 0; a < g.verts.size(); ++a)
    for (int v : g.verts[a]) node_of_sample[size_t(v)] = int(a);
  sk.vertex_node.assign(size_t(n), 0);
  if (st.samples == n) {
    for (int i = 0; i < n; ++i) sk.vertex_node[size_t(i)] = node_of_sample[size_t(i)];
  } else {
    const PointKdTree sample_tree(sampled);
    for (int i = 0; i < n; ++i) sk.vertex_node[size_t(i)] = node_of_sample[size_t(sample_tree.nearest_one(points[size_t(i)]))];
  }
  place_nodes(sk, points);
  st.seconds = total.seconds();
  if (progress)
    progress("point skeleton: " + std::to_string(sk.nodes.size()) + " nodes (" + std::to_string(st.sampled_nodes) + " sampled, " +
             std::to_string(st.collapsed_triangles) + " triangles collapsed, " + std::to_string(st.dropped_cycles) + " narrow cycles opened, " +
             std::to_string(st.pruned_branches) + " short branches pruned)");
  if (stats) *stats = st;
  return sk;
}

std::vector<double> node_radii(const Skeleton& s, const std::vector<Eigen::Vector3d>& points) {
  const auto adj = s.adjacency();
  std::vector<double> sum(s.nodes.size(), 0.0);
  std::vector<int> count(s.nodes.size(), 0);
  for (size_t i = 0; i < points.size() && i < s.vertex_node.size(); ++i) {
    const int a = s.vertex_node[i];
    const Eigen::Vector3d& p = points[i];
    double best = (p - s.nodes[size_t(a)]).norm();
    for (int b : adj[size_t(a)]) {
      const Eigen::Vector3d u = s.nodes[size_t(b)] - s.nodes[size_t(a)];
      const double t = std::clamp((p - s.nodes[size_t(a)]).dot(u) / std::max(u.squaredNorm(), 1e-300), 0.0, 1.0);
      best = std::min(best, (p - s.nodes[size_t(a)] - t * u).norm());
    }
    sum[size_t(a)] += best, ++count[size_t(a)];
  }
  for (size_t a = 0; a < sum.size(); ++a) sum[a] /= std::max(count[a], 1);
  return sum;
}

}  // namespace sdm
