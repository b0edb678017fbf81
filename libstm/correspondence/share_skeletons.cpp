#include "libstm/correspondence/share_skeletons.h"

#include "libstm/core/errors.h"
#include "libstm/core/id_value.h"
#include "libstm/geometry/differential_geometry.h"
#include "libstm/layout/segments.h"
#include "libstm/skeleton/common_branching.h"
#include "libstm/skeleton/exchange_branches.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace sdm {

namespace {

// A chain of the shared graph as a polyline in one model, oriented like the source's chain.
struct Polyline {
  std::vector<Eigen::Vector3d> p;
  std::vector<double> s;  // arc length at every point
  double total() const { return s.back(); }

  explicit Polyline(std::vector<Eigen::Vector3d> pts) : p(std::move(pts)) {
    s.assign(p.size(), 0.0);
    for (size_t k = 1; k < p.size(); ++k) s[k] = s[k - 1] + (p[k] - p[k - 1]).norm();
  }
  Eigen::Vector3d at(double f) const {
    const double target = f * total();
    for (size_t k = 0; k + 1 < p.size(); ++k) {
      const double l = s[k + 1] - s[k];
      if (s[k + 1] >= target || k + 2 == p.size()) return l > 0 ? p[k] + (p[k + 1] - p[k]) * std::clamp((target - s[k]) / l, 0.0, 1.0) : p[k];
    }
    return p.front();
  }
  // Arc-length fraction of the point of the polyline nearest to q.
  double project(const Eigen::Vector3d& q) const {
    if (!(total() > 0)) return 0;
    double best = INFINITY, best_s = 0;
    for (size_t k = 0; k + 1 < p.size(); ++k) {
      double t = 0;
      const double d = distance_to_segment(q, p[k], p[k + 1], &t);
      if (d < best) best = d, best_s = s[k] + std::clamp(t, 0.0, 1.0) * (s[k + 1] - s[k]);
    }
    return best_s / total();
  }
};

// One model's side of the resampling: the reduced skeleton's chains expressed in the source's
// chain numbering and direction.
struct Side {
  const Mesh* mesh;
  const Skeleton* sk;
  std::vector<int> key_node;                 // shared key k -> this skeleton's node
  std::vector<int> chain;                    // source chain c -> this skeleton's chain
  std::vector<char> reversed;                // traversed against its stored direction
  std::vector<Polyline> lines;               // per source chain
  std::vector<int> edge_chain;               // this skeleton's edge -> source chain
  std::vector<Eigen::Vector3d> key_position;  // shared key k's position (a pure cycle's may move)
};

// A chain's mean radius, its segments weighted by their lengths.
double chain_radius(const ReducedSkeleton::Chain& c, const std::vector<SegmentGeometry>& geo) {
  double sum = 0, len = 0;
  for (int e : c.edges) sum += geo[e].radius * std::max(geo[e].length, 1e-300), len += std::max(geo[e].length, 1e-300);
  return len > 0 ? sum / len : 0;
}

// The shared graph's numbering (shared_graph): keys first, then every chain's inner nodes.
struct SharedGraph {
  int keys = 0, total_nodes = 0;
  std::vector<int> segments;                  // per chain of the source: its edge count
  std::vector<std::vector<int>> inner;        // per chain: its inner nodes, in order
  std::vector<std::array<int, 2>> edges;      // chain by chain
  std::vector<std::vector<int>> chain_edges;  // per chain: its edges, in order
};

// Shared skeleton for one side: nodes placed on its polylines, vertices reassigned.
Skeleton resample(const Side& side, const ReducedSkeleton& red, const SharedGraph& graph, const std::vector<int>& key_of_node) {
  const std::vector<int>& n = graph.segments;
  const std::vector<std::vector<int>>& inner = graph.inner;
  const int nk = graph.keys, total_nodes = graph.total_nodes;
  const Skeleton& sk = *side.sk;
  const Mesh& mesh = *side.mesh;
  Skeleton out;
  out.nodes.resize(total_nodes);
  out.edges = graph.edges;
  for (int k = 0; k < nk; ++k) out.nodes[k] = side.key_position[k];
  const int nc = int(n.size());
  for (int c = 0; c < nc; ++c)
    for (int j = 1; j < n[c]; ++j) out.nodes[inner[c][j - 1]] = side.lines[c].at(double(j) / n[c]);
  auto node_at = [&](int c, int j) {
    const auto& ch = red.chains[side.chain[c]];
    if (j <= 0) return key_of_node[side.reversed[c] ? ch.nodes.back() : ch.nodes.front()];
    if (j >= n[c]) return key_of_node[side.reversed[c] ? ch.nodes.front() : ch.nodes.back()];
    return inner[c][j - 1];
  };
  std::vector<std::vector<int>> node_edges(sk.nodes.size());
  for (size_t e = 0; e < sk.edges.size(); ++e) {
    node_edges[sk.edges[e][0]].push_back(int(e));
    if (sk.edges[e][1] != sk.edges[e][0]) node_edges[sk.edges[e][1]].push_back(int(e));
  }
  const int nv = int(mesh.n_vertices());
  out.vertex_node.assign(nv, -1);
  std::vector<int> v_chain(nv, -1);
  std::vector<double> v_arc(nv, 0);
  for (auto v : mesh.vertices()) {
    const int x = sk.vertex_node[v.idx()];
    const Eigen::Vector3d p = point(mesh, v);
    int best = -1;
    double best_d = INFINITY;
    for (int e : node_edges[x]) {
      const double d = distance_to_segment(p, sk.nodes[sk.edges[e][0]], sk.nodes[sk.edges[e][1]]);
      if (d < best_d * (1 - 1e-12)) best = e, best_d = d;
    }
    if (best < 0) {  // an isolated node: a key of its own
      out.vertex_node[v.idx()] = key_of_node[x];
      continue;
    }
    const int c = side.edge_chain[best];
    const double f = side.lines[c].project(p);
    v_chain[v.idx()] = c;
    v_arc[v.idx()] = f;
    out.vertex_node[v.idx()] = node_at(c, int(std::lround(f * n[c])));
  }
  // Nodes left without a vertex borrow the nearest one (in arc length along their chain, or in
  // space for a key) from a node that owns more than one.
  std::vector<int> count(total_nodes, 0);
  for (int x : out.vertex_node) ++count[x];
  auto borrow = [&](int node, auto distance) {
    int best = -1;
    double best_d = INFINITY;
    for (int v = 0; v < nv; ++v) {
      if (count[out.vertex_node[v]] < 2) continue;
      const double d = distance(v);
      if (d < best_d) best_d = d, best = v;
    }
    if (best < 0) return;
    --count[out.vertex_node[best]];
    out.vertex_node[best] = node;
    ++count[node];
  };
  for (int c = 0; c < nc; ++c)
    for (int j = 1; j < n[c]; ++j) {
      const int node = inner[c][j - 1];
      if (count[node] > 0) continue;
      const double f = double(j) / n[c];
      borrow(node, [&](int v) {
        return v_chain[v] == c ? std::abs(v_arc[v] - f) : 1e3 + (point(mesh, mesh.vertex_handle(v)) - out.nodes[node]).norm();
      });
    }
  for (int k = 0; k < nk; ++k)
    if (count[k] == 0) borrow(k, [&](int v) { return (point(mesh, mesh.vertex_handle(v)) - out.nodes[k]).norm(); });
  return out;
}

// The given (source node, target node) pairs in the pruned skeletons' numbering; a pair out of
// range goes on unchanged (match_skeletons names it). Throws InputError for a node on a pruned branch.
std::vector<std::pair<int, int>> fixed_in_common(const CommonBranching& common, const std::vector<std::pair<int, int>>& given) {
  std::vector<std::pair<int, int>> fixed;
  for (auto [x, y] : given) {
    const bool in_range = x >= 0 && y >= 0 && x < int(common.a_node.size()) && y < int(common.b_node.size());
    if (in_range && (common.a_node[x] < 0 || common.b_node[y] < 0))
      throw InputError("--match " + std::to_string(x) + "=" + std::to_string(y) + ": the node lies on a branch pruned to match the other skeleton");
    fixed.push_back(in_range ? std::make_pair(common.a_node[x], common.b_node[y]) : std::make_pair(x, y));
  }
  return fixed;
}

// Both sides' key nodes and positions: key k is m.a.keys[k] in a and its match in b.
void set_keys(const SkeletonMatch& m, Side& sa, Side& sb) {
  for (size_t k = 0; k < m.a.keys.size(); ++k) {
    sa.key_node.push_back(m.a.keys[k]);
    sb.key_node.push_back(m.b.keys[m.key_a_to_b[k]]);
    sa.key_position.push_back(sa.sk->nodes[sa.key_node[k]]);
    sb.key_position.push_back(sb.sk->nodes[sb.key_node[k]]);
  }
}

// The mean of the skeleton's nodes (into c) and their RMS distance to it.
double centre_and_size(const Skeleton& s, Eigen::Vector3d& c) {
  c.setZero();
  for (const auto& p : s.nodes) c += p;
  c /= double(std::max<size_t>(1, s.nodes.size()));
  double r2 = 0;
  for (const auto& p : s.nodes) r2 += (p - c).squaredNorm();
  return std::sqrt(r2 / double(std::max<size_t>(1, s.nodes.size())));
}

// A pure cycle's closed polyline (last point = first) restarted at its point nearest to `start`:
// its key node is an arbitrary node of the ring (reduce_skeleton), so b's ring starts over where
// a's key lands, and the two rings line up. No zero-length piece where the new start falls on a node.
std::vector<Eigen::Vector3d> restart_ring(const std::vector<Eigen::Vector3d>& pb, const Eigen::Vector3d& start) {
  const Polyline ring(pb);
  const double f0 = ring.project(start);
  std::vector<Eigen::Vector3d> shifted{ring.at(f0)};
  for (size_t k = 1; k < pb.size(); ++k)
    if (ring.s[k] / ring.total() > f0) shifted.push_back(pb[k]);
  for (size_t k = 1; k < pb.size(); ++k)
    if (ring.s[k] / ring.total() <= f0) shifted.push_back(pb[k]);
  shifted.push_back(shifted.front());
  std::vector<Eigen::Vector3d> out;
  for (const auto& q : shifted)
    if (out.empty() || (q - out.back()).norm() > 1e-12 * std::max(1.0, ring.total())) out.push_back(q);
  if ((out.back() - shifted.front()).norm() > 0) out.push_back(shifted.front());
  return out;
}

// Segments for one matched pair of chains (share_skeletons' rule): the larger edge count, raised
// so no segment is longer than split_ratio mean radii on either side; at least 3 for a loop; 1-1000.
int chain_segments(const ReducedSkeleton::Chain& ca, const ReducedSkeleton::Chain& cb, const Polyline& la, const Polyline& lb,
                   const std::vector<SegmentGeometry>& geo_a, const std::vector<SegmentGeometry>& geo_b, double split_ratio) {
  double want = double(std::max(ca.edges.size(), cb.edges.size()));
  if (split_ratio > 0 && std::isfinite(split_ratio)) {
    const double ra = chain_radius(ca, geo_a), rb = chain_radius(cb, geo_b);
    if (ra > 0) want = std::max(want, std::ceil(la.total() / (split_ratio * ra) - 1e-9));
    if (rb > 0) want = std::max(want, std::ceil(lb.total() / (split_ratio * rb) - 1e-9));
  }
  if (ca.from == ca.to) want = std::max(want, 3.0);  // a loop needs three segments to stay a cycle of capsules
  return int(std::clamp(want, 1.0, 1000.0));
}

// Per chain c of m.a: both sides' polylines (b's oriented like a's), chain numbers and edge ->
// chain maps; returns the segments per chain. A pure cycle's start is arbitrary, and so is the
// match's rotation about its axis (it aligns the rings' starts): b's ring is lined up by pose, a's
// start placed on b by the skeletons' centres and RMS sizes.
std::vector<int> chain_polylines(const SkeletonMatch& m, double split_ratio, Side& sa, Side& sb) {
  const Skeleton& a = *sa.sk;
  const Skeleton& b = *sb.sk;
  const std::vector<SegmentGeometry> geo_a = segment_geometry(*sa.mesh, a, assign_faces(*sa.mesh, a));
  const std::vector<SegmentGeometry> geo_b = segment_geometry(*sb.mesh, b, assign_faces(*sb.mesh, b));
  Eigen::Vector3d ca0, cb0;
  const double size_a = centre_and_size(a, ca0), size_b = centre_and_size(b, cb0);
  sa.edge_chain.assign(a.edges.size(), -1);
  sb.edge_chain.assign(b.edges.size(), -1);
  const int nc = int(m.a.chains.size());
  std::vector<int> n(nc, 1);
  for (int c = 0; c < nc; ++c) {
    const auto& ca = m.a.chains[c];
    const auto [cbi, rev] = m.chain_a_to_b[c];
    const auto& cb = m.b.chains[cbi];
    sa.chain.push_back(c), sa.reversed.push_back(0);
    sb.chain.push_back(cbi), sb.reversed.push_back(rev ? 1 : 0);
    std::vector<Eigen::Vector3d> pa, pb;
    for (int x : ca.nodes) pa.push_back(a.nodes[x]);
    for (int x : cb.nodes) pb.push_back(b.nodes[x]);
    if (rev) std::reverse(pb.begin(), pb.end());
    if (ca.from == ca.to && m.a.key_degree[ca.from] == 2 && pb.size() > 2) {
      pb = restart_ring(pb, cb0 + (size_a > 0 ? size_b / size_a : 1.0) * (pa.front() - ca0));
      sb.key_position[ca.from] = pb.front();
    }
    sa.lines.emplace_back(pa);
    sb.lines.emplace_back(pb);
    for (int e : ca.edges) sa.edge_chain[e] = c;
    for (int e : cb.edges) sb.edge_chain[e] = c;
    n[c] = chain_segments(ca, cb, sa.lines.back(), sb.lines.back(), geo_a, geo_b, split_ratio);
  }
  return n;
}

// The shared graph: keys first, then every chain's inner nodes; edges chain by chain, each chain
// of `red` cut into segments[c] edges.
SharedGraph shared_graph(const ReducedSkeleton& red, const std::vector<int>& segments) {
  SharedGraph graph;
  graph.keys = int(red.keys.size());
  graph.segments = segments;
  const int nc = int(segments.size());
  graph.inner.resize(nc);
  graph.total_nodes = graph.keys;
  graph.chain_edges.resize(nc);
  for (int c = 0; c < nc; ++c) {
    const auto& ca = red.chains[c];
    std::vector<int> path{ca.from};
    for (int j = 1; j < segments[c]; ++j) graph.inner[c].push_back(graph.total_nodes), path.push_back(graph.total_nodes++);
    path.push_back(ca.to);
    for (size_t i = 0; i + 1 < path.size(); ++i) {
      graph.chain_edges[c].push_back(int(graph.edges.size()));
      graph.edges.push_back({path[i], path[i + 1]});
    }
  }
  return graph;
}

// The rotation that best takes the nodes a onto the nodes b (Kabsch over corresponding nodes), or
// `fallback` when the nodes are too few to fix one (a single straight chain: second singular value
// under 1e-9 of the first).
Eigen::Matrix3d rotation_between(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                                 const Eigen::Matrix3d& fallback) {
  const int total_nodes = int(a.size());
  Eigen::Vector3d sa0 = Eigen::Vector3d::Zero(), sb0 = Eigen::Vector3d::Zero();
  for (int i = 0; i < total_nodes; ++i) sa0 += a[i] / total_nodes, sb0 += b[i] / total_nodes;
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (int i = 0; i < total_nodes; ++i) H += (a[i] - sa0) * (b[i] - sb0).transpose();
  // H = sum a b^T takes b onto a; its nearest rotation, transposed, takes a onto b. Transposed
  // rather than the rotation nearest to H^T: this is bit for bit the V D U^T of H's SVD that the
  // demo transfers were made with (the SVD of H^T rounds differently).
  double second = 0;
  Eigen::Matrix3d R;
  R = nearest_rotation(H, nullptr, &second).transpose();
  if (second <= 1e-9) return fallback;
  return R;
}

}  // namespace

namespace {

// The common branching's skeletons resampled onto one graph through the match `m` of them.
SharedSkeletons share_through(const Mesh& mesh_a, const Mesh& mesh_b, const CommonBranching& common, SkeletonMatch match,
                              double split_ratio) {
  SharedSkeletons r;
  const Skeleton& a = common.a;
  const Skeleton& b = common.b;
  r.pruned_a = common.pruned_a, r.pruned_b = common.pruned_b;
  r.slid_a = common.slid_a, r.slid_b = common.slid_b, r.length_disagreement = common.length_disagreement;
  r.node_a = common.a_original, r.node_b = common.b_original;
  r.match = std::move(match);
  const SkeletonMatch& m = r.match;
  Side sa{&mesh_a, &a, {}, {}, {}, {}, {}, {}}, sb{&mesh_b, &b, {}, {}, {}, {}, {}, {}};
  set_keys(m, sa, sb);
  const SharedGraph graph = shared_graph(m.a, chain_polylines(m, split_ratio, sa, sb));
  r.chain_edges = graph.chain_edges;
  std::vector<int> key_a(a.nodes.size(), -1), key_b(b.nodes.size(), -1);
  for (int k = 0; k < graph.keys; ++k) key_a[sa.key_node[k]] = k, key_b[sb.key_node[k]] = k;
  r.a = resample(sa, m.a, graph, key_a);
  r.b = resample(sb, m.b, graph, key_b);
  // The match's rotation, except around pure cycles lined up above.
  r.rotation = rotation_between(r.a.nodes, r.b.nodes, m.rotation);
  return r;
}

}  // namespace

SharedSkeletons share_skeletons(const Mesh& mesh_a, const Skeleton& given_a, const Mesh& mesh_b, const Skeleton& given_b,
                                const std::vector<std::pair<int, int>>& given_fixed, double split_ratio) {
  // Extracted skeletons of one shape can differ by a small branch (a tail found in one
  // tessellation only): both are pruned to their common branching first.
  const CommonBranching common = common_branching(given_a, given_b);
  return share_through(mesh_a, mesh_b, common, match_skeletons(common.a, common.b, fixed_in_common(common, given_fixed)), split_ratio);
}

std::vector<SharedSkeletons> share_skeletons_candidates(const Mesh& mesh_a, const Skeleton& given_a, const Mesh& mesh_b,
                                                        const Skeleton& given_b, const std::vector<std::pair<int, int>>& given_fixed,
                                                        double split_ratio, int count) {
  const CommonBranching common = common_branching(given_a, given_b);
  std::vector<SharedSkeletons> out;
  auto add = [&](const CommonBranching& c, bool exchanged) {
    for (SkeletonMatch& m : match_candidates(c.a, c.b, fixed_in_common(c, given_fixed), count)) {
      out.push_back(share_through(mesh_a, mesh_b, c, std::move(m), split_ratio));
      out.back().exchanged = exchanged;
    }
  };
  add(common, false);
  // A pair of limbs split between two close junctions the other way round in the other skeleton
  // is matched crossed whatever the shapes say: the pair exchanged gives the other assignment.
  if (given_fixed.empty()) {
    for (Skeleton& v : exchanged_branches(common.a)) {
      CommonBranching c = common;
      c.a = std::move(v);
      add(c, true);
    }
  }
  return out;
}

SkeletonMatch match_in_given_numbering(const SharedSkeletons& shared) {
  SkeletonMatch m = shared.match;
  for (int& k : m.a.keys) k = shared.node_a[k];
  for (int& k : m.b.keys) k = shared.node_b[k];
  return m;
}

Skeleton skeleton_onto_graph(const Skeleton& graph, const Skeleton& target, const std::vector<std::pair<int, int>>& fixed,
                             SkeletonMatch* match) {
  const SkeletonMatch m = match_skeletons(graph, target, fixed);
  Skeleton out;
  out.nodes = graph.nodes;
  out.edges = graph.edges;
  for (size_t k = 0; k < m.a.keys.size(); ++k) out.nodes[m.a.keys[k]] = target.nodes[m.b.keys[m.key_a_to_b[k]]];
  for (size_t c = 0; c < m.a.chains.size(); ++c) {
    const auto& ca = m.a.chains[c];
    const auto& cb = m.b.chains[m.chain_a_to_b[c].first];
    std::vector<Eigen::Vector3d> pg, pt;
    for (int x : ca.nodes) pg.push_back(graph.nodes[x]);
    for (int x : cb.nodes) pt.push_back(target.nodes[x]);
    if (m.chain_a_to_b[c].second) std::reverse(pt.begin(), pt.end());
    const Polyline lg(pg), lt(pt);
    for (size_t j = 1; j + 1 < ca.nodes.size(); ++j)
      out.nodes[ca.nodes[j]] = lt.at(lg.total() > 0 ? lg.s[j] / lg.total() : double(j) / double(ca.nodes.size() - 1));
  }
  if (match) *match = m;
  return out;
}

std::vector<std::pair<int, int>> parse_node_pairs(const std::vector<std::string>& items) {
  std::vector<std::pair<int, int>> out;
  for (const auto& s : items) {
    const std::string form = "--match " + s + ": expected SOURCE_NODE=TARGET_NODE (two skeleton node indices)";
    const IdValue pair = parse_id_value(s, form);
    out.push_back({pair.id, parse_whole_number(pair.value, form)});
  }
  return out;
}

}  // namespace sdm
