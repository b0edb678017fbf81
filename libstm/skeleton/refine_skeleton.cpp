#include "libstm/skeleton/refine_skeleton.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <tuple>

namespace sdm {

namespace {

// The graph during refinement: adjacency kept sorted, merged nodes marked dead (compacted at the
// end), merges that keep nodes and edges inside.
class Refinement {
 public:
  Refinement(SkeletonGraph& g, const Eigen::MatrixX3d& O, const InsideMesh& in, const TriangleBvh& surface, double diag,
             const SkeletonOptions& opt);
  bool prune_short_branches();
  bool merge_short_edges();
  void place_all();
  void finish();

 private:
  Eigen::Vector3d com(const std::vector<int>& vs) const;
  double radius(int a) const;
  bool node_ok(int a, const Eigen::Vector3d& p) const;
  bool merge(int a, int b, bool force);
  void place(int a);

  SkeletonGraph& g_;
  const Eigen::MatrixX3d& O_;
  const InsideMesh& in_;
  const TriangleBvh& surface_;
  const SkeletonOptions& opt_;
  const int n_;
  std::vector<char> alive_;
  std::vector<std::vector<int>> adj_;
  double min_branch_ = 0, max_radius_ = 0;
};

Refinement::Refinement(SkeletonGraph& g, const Eigen::MatrixX3d& O, const InsideMesh& in, const TriangleBvh& surface,
                       double diag, const SkeletonOptions& opt)
    : g_(g), O_(O), in_(in), surface_(surface), opt_(opt), n_(int(g.pos.size())), alive_(n_, 1), adj_(n_) {
  for (const auto& e : g.edges) adj_[e.first].push_back(e.second), adj_[e.second].push_back(e.first);
  for (auto& a : adj_) std::sort(a.begin(), a.end());
  min_branch_ = opt.min_branch * diag;
  for (int a = 0; a < n_; ++a) max_radius_ = std::max(max_radius_, radius(a));
}

// Centre of mass of original vertices.
Eigen::Vector3d Refinement::com(const std::vector<int>& vs) const {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int v : vs) c += O_.row(v).transpose();
  return Eigen::Vector3d(c / double(vs.size()));
}

// Mean distance from node a to its vertices: the local radius of the shape.
double Refinement::radius(int a) const {
  double r = 0;
  for (int v : g_.verts[a]) r += (O_.row(v).transpose() - g_.pos[a]).norm();
  return r / g_.verts[a].size();
}

// Node a at p and its edges lie inside.
bool Refinement::node_ok(int a, const Eigen::Vector3d& p) const {
  if (!in_.inside(p)) return false;
  for (int b : adj_[a])
    if (in_.segment_crosses(p, g_.pos[b])) return false;
  return true;
}

// Merges b into a; returns false (and changes nothing) when a's new position and edges cannot
// be kept inside (unless forced) or when a cycle would lose a segment below three.
bool Refinement::merge(int a, int b, bool force) {
  std::vector<int> common;
  std::set_intersection(adj_[a].begin(), adj_[a].end(), adj_[b].begin(), adj_[b].end(), std::back_inserter(common));
  if (!common.empty()) return false;
  std::vector<int> vs = g_.verts[a];
  vs.insert(vs.end(), g_.verts[b].begin(), g_.verts[b].end());
  std::vector<int> nb;
  for (int x : adj_[a])
    if (x != b) nb.push_back(x);
  for (int x : adj_[b])
    if (x != a) nb.push_back(x);
  Eigen::Vector3d p = com(vs);
  auto ok = [&](const Eigen::Vector3d& q) {
    if (!in_.inside(q)) return false;
    for (int x : nb)
      if (in_.segment_crosses(q, g_.pos[x])) return false;
    return true;
  };
  if (!ok(p)) {
    const Eigen::Vector3d alt[2] = {g_.pos[a], g_.pos[b]};
    bool found = false;
    for (const auto& q : alt)
      if (ok(q)) {
        p = q, found = true;
        break;
      }
    if (!found && !force) return false;
    if (!found) p = g_.pos[a];
  }
  g_.verts[a] = std::move(vs);
  g_.verts[b].clear();
  g_.pos[a] = p;
  alive_[b] = 0;
  for (int x : adj_[b]) {
    erase_sorted(adj_[x], b);
    if (x != a) insert_sorted(adj_[x], a), insert_sorted(adj_[a], x);
  }
  adj_[b].clear();
  erase_sorted(adj_[a], b);
  return true;
}

// End branches shorter than min_branch, or ending inside their junction's inscribed ball: merged
// into the junction they hang from.
bool Refinement::prune_short_branches() {
  bool changed = false;
  for (int a = 0; a < n_; ++a) {
    if (!alive_[a] || adj_[a].size() != 1) continue;
    std::vector<int> chain = {a};
    double len = 0;
    int prev = a, cur = adj_[a][0];
    len += (g_.pos[a] - g_.pos[cur]).norm();
    const double limit = std::max(min_branch_, opt_.prune_radius * max_radius_);  // walk no further
    while (adj_[cur].size() == 2 && len < limit) {
      const int next = adj_[cur][0] == prev ? adj_[cur][1] : adj_[cur][0];
      chain.push_back(cur);
      len += (g_.pos[cur] - g_.pos[next]).norm();
      prev = cur, cur = next;
    }
    // A branch that does not reach out of its junction's inscribed ball is a bump, not a limb.
    if (adj_[cur].size() >= 3 &&
        (len < min_branch_ || len < opt_.prune_radius * surface_.closest_point(g_.pos[cur]).distance)) {
      for (auto it = chain.rbegin(); it != chain.rend(); ++it) merge(cur, *it, true);
      changed = true;
    }
  }
  return changed;
}

// Short edges: shorter than the local radius (or than min_branch), shortest relative first; each
// node takes part in one merge per pass.
bool Refinement::merge_short_edges() {
  std::vector<std::tuple<double, int, int>> cand;
  for (int a = 0; a < n_; ++a) {
    if (!alive_[a]) continue;
    const double ra = radius(a);
    for (int b : adj_[a]) {
      if (b < a) continue;
      const double len = (g_.pos[a] - g_.pos[b]).norm();
      const double lim = std::max(opt_.segment_radius * std::min(ra, radius(b)), min_branch_);
      if (len < lim) cand.emplace_back(len / lim, a, b);
    }
  }
  std::sort(cand.begin(), cand.end());
  std::vector<char> touched(n_, 0);
  bool changed = false;
  for (const auto& [r, a, b] : cand) {
    if (touched[a] || touched[b] || !alive_[a] || !alive_[b]) continue;
    // Keep the node with more vertices, so ends and junctions stay where the mass is.
    const bool keep_a = g_.verts[a].size() >= g_.verts[b].size();
    if (merge(keep_a ? a : b, keep_a ? b : a, true)) touched[a] = touched[b] = 1, changed = true;
  }
  return changed;
}

// Positions: centre of the original vertices; when that leaves the volume (or lies on the
// surface, as the centre of a flat cap does) or an edge crosses the surface, pulled back toward
// the contracted position, then nudged along the node's edges into the volume.
void Refinement::place(int a) {
  if (node_ok(a, g_.pos[a])) return;
  const Eigen::Vector3d target = g_.pos[a], back = g_.fallback[a];
  for (double t = 0.75; t > 0.01; t -= 0.25) {
    const Eigen::Vector3d q = back + t * (target - back);
    if (node_ok(a, q)) {
      g_.pos[a] = q;
      return;
    }
  }
  if (node_ok(a, back)) {
    g_.pos[a] = back;
    return;
  }
  for (double t : {0.02, 0.05, 0.1, 0.2, 0.35, 0.5})
    for (int b : adj_[a]) {
      const Eigen::Vector3d q = target + t * (g_.pos[b] - target);
      if (node_ok(a, q)) {
        g_.pos[a] = q;
        return;
      }
    }
}

void Refinement::place_all() {
  std::vector<Eigen::Vector3d> wanted(g_.pos.begin(), g_.pos.end());
  for (int a = 0; a < n_; ++a)
    if (alive_[a]) place(a);
  // A node moved because an edge to a neighbour's old place crossed the surface goes back where it
  // wanted to be when, with the neighbours where they ended, it and its edges lie inside (its
  // neighbours' other edges are unchanged, so they stay inside too).
  for (int a = 0; a < n_; ++a)
    if (alive_[a] && g_.pos[a] != wanted[a] && node_ok(a, wanted[a])) g_.pos[a] = wanted[a];
}

// The merged nodes leave the graph; the adjacency becomes its edges.
void Refinement::finish() {
  std::set<std::pair<int, int>> edges;
  for (int a = 0; a < n_; ++a)
    if (alive_[a])
      for (int b : adj_[a])
        if (a < b) edges.insert({a, b});
  g_ = keep_nodes(g_, alive_, edges);
}

// The chain of degree-2 nodes from `start` away from its neighbour `keep`, when it ends at an end
// node (not back at keep): the nodes of that end branch, start first. Empty otherwise.
std::vector<int> end_branch(const std::vector<std::vector<int>>& adj, int keep, int start) {
  std::vector<int> chain = {start};
  int prev = keep, cur = start;
  while (adj[cur].size() == 2) {
    const int next = adj[cur][0] == prev ? adj[cur][1] : adj[cur][0];
    prev = cur, cur = next;
    if (cur == keep) break;
    chain.push_back(cur);
  }
  if (adj[cur].size() != 1 || cur == keep) return {};
  return chain;
}

// Bends edge a-b through the medial pole (of a vertex owned by a node of at least two) that sees
// both ends from inside with the shortest detour (the first met among equal ones). False when there
// is none. The candidates are tried shortest first, so the first that passes is the one; the ends'
// own inside tests are made once (trying every shorter candidate in turn, with both ends' tests
// each time, was most of a small mesh's refinement: rotor 2.0 ms).
bool bend_edge(SkeletonGraph& g, int a, int b, const InsideMesh& in, const Eigen::MatrixX3d& poles) {
  const Eigen::Vector3d pa = g.pos[a], pb = g.pos[b];
  if (!in.inside(pa) || !in.inside(pb)) return false;
  struct Detour {
    double length;
    int owner, v;
  };
  std::vector<Detour> detours;
  for (int owner = 0; owner < int(g.verts.size()); ++owner) {
    if (g.verts[owner].size() < 2) continue;
    for (int v : g.verts[owner]) {
      const Eigen::Vector3d p = poles.row(v);
      detours.push_back({(p - pa).norm() + (p - pb).norm(), owner, v});
    }
  }
  std::stable_sort(detours.begin(), detours.end(), [](const Detour& x, const Detour& y) { return x.length < y.length; });
  int bv = -1, from = -1;
  for (const Detour& d : detours) {
    const Eigen::Vector3d p = poles.row(d.v);
    if (in.segment_crosses(pa, p) || in.segment_crosses(p, pb) || !in.inside(p)) continue;
    bv = d.v, from = d.owner;
    break;
  }
  if (bv < 0) return false;
  const int c = int(g.pos.size());
  g.pos.push_back(poles.row(bv));
  g.fallback.push_back(poles.row(bv));
  auto& vs = g.verts[from];
  vs.erase(std::find(vs.begin(), vs.end(), bv));
  g.verts.push_back({bv});
  g.edges.erase({a, b});
  g.edges.insert({std::min(a, c), std::max(a, c)});
  g.edges.insert({std::min(b, c), std::max(b, c)});
  return true;
}

}  // namespace

void refine_skeleton(SkeletonGraph& g, const Eigen::MatrixX3d& original, const InsideMesh& inside,
                     const TriangleBvh& surface, double diag, const SkeletonOptions& options) {
  Refinement r(g, original, inside, surface, diag, options);
  for (bool changed = true; changed;) {
    changed = r.prune_short_branches();
    changed = r.merge_short_edges() || changed;
  }
  r.place_all();
  r.finish();
}

void centre_junctions(SkeletonGraph& g, const Eigen::MatrixX3d& original, const Eigen::MatrixX3d& poles,
                      const InsideMesh& inside, double reach) {
  const std::vector<std::vector<int>> adj = g.adjacency();
  for (size_t a = 0; a < g.pos.size(); ++a) {
    if (adj[a].size() < 3) continue;
    int best = -1;
    double widest = -1;
    for (int v : g.verts[a]) {
      const double r = (poles.row(v) - original.row(v)).squaredNorm();
      if (r > widest) widest = r, best = v;
    }
    // Only within the ball: further away the widest ball belongs to a branch, not the crossing.
    if (best < 0 || (poles.row(best).transpose() - g.pos[a]).squaredNorm() > reach * reach * widest) continue;
    const Eigen::Vector3d p = poles.row(best);
    bool ok = inside.inside(p);
    for (int b : adj[a]) ok = ok && !inside.segment_crosses(p, g.pos[b]);
    if (ok) g.pos[a] = p;
  }
}

void bend_crossing_edges(SkeletonGraph& g, const InsideMesh& inside, const Eigen::MatrixX3d& poles) {
  const std::vector<std::pair<int, int>> edges(g.edges.begin(), g.edges.end());
  std::vector<std::pair<int, int>> dead_ends;
  for (const auto& [a, b] : edges)
    if (!inside.segment_inside(g.pos[a], g.pos[b]) && !bend_edge(g, a, b, inside, poles)) dead_ends.push_back({a, b});
  // No detour: when the edge leads to an end branch, the branch goes into the node on the other
  // side.
  std::vector<char> gone(g.pos.size(), 0);
  for (const auto& [a, b] : dead_ends) {
    const std::vector<std::vector<int>> adj = g.adjacency();
    for (const auto& [keep, start] : {std::make_pair(a, b), std::make_pair(b, a)}) {
      const std::vector<int> chain = end_branch(adj, keep, start);
      if (chain.empty()) continue;
      for (int x : chain) {
        g.verts[keep].insert(g.verts[keep].end(), g.verts[x].begin(), g.verts[x].end());
        g.verts[x].clear();
        gone[x] = 1;
      }
      for (auto it = g.edges.begin(); it != g.edges.end();)
        it = gone[it->first] || gone[it->second] ? g.edges.erase(it) : std::next(it);
      break;
    }
  }
  if (std::find(gone.begin(), gone.end(), 1) == gone.end()) return;
  std::vector<char> keep(gone.size());
  for (size_t x = 0; x < gone.size(); ++x) keep[x] = !gone[x];
  g = keep_nodes(g, keep, g.edges);
}

void split_lone_node(SkeletonGraph& g, const Eigen::MatrixX3d& X, const InsideMesh& in) {
  if (g.pos.size() != 1 || !g.edges.empty() || g.verts[0].size() < 2) return;
  const std::vector<int>& vs = g.verts[0];
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int v : vs) c += X.row(v).transpose();
  c /= double(vs.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int v : vs) {
    const Eigen::Vector3d d = X.row(v).transpose() - c;
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Eigen::Vector3d axis = eig.eigenvectors().col(2);
  // The sign of an eigenvector is arbitrary: take the one towards the longer side, so that a
  // rotated input gives the rotated skeleton.
  double lo = 0, hi = 0;
  for (int v : vs) {
    const double t = (X.row(v).transpose() - c).dot(axis);
    lo = std::min(lo, t), hi = std::max(hi, t);
  }
  if (-lo > hi) axis = -axis, std::swap(lo, hi), lo = -lo, hi = -hi;
  Eigen::Vector3d a = c + 0.5 * lo * axis, b = c + 0.5 * hi * axis;
  for (int k = 0; k < 8 && !(in.inside(a) && in.inside(b) && in.segment_inside(a, b)); ++k)
    a = c + 0.5 * (a - c), b = c + 0.5 * (b - c);
  SkeletonGraph out;
  out.pos = {a, b};
  out.fallback = {g.fallback[0], g.fallback[0]};
  out.verts.resize(2);
  for (int v : vs) out.verts[(X.row(v).transpose() - c).dot(axis) >= 0 ? 1 : 0].push_back(v);
  if (out.verts[0].empty() || out.verts[1].empty()) return;
  out.edges.insert({0, 1});
  g = std::move(out);
}

}  // namespace sdm
