#include "libstm/skeleton/common_branching.h"

#include "libstm/core/errors.h"
#include "libstm/skeleton/match_skeletons.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <sstream>

namespace sdm {
namespace {

// One reduction of a skeleton: an end branch pruned (its nodes go to `junction`), or a chain
// between two junctions contracted (its inner nodes and `other` merge into `junction`).
struct Change {
  bool join = false;
  int end = -1, junction = -1, other = -1;
  std::vector<int> removed;  // pruned: the end node and the chain's inner nodes; joined: the inner nodes
  double significance = 0;   // share of the skeleton's length (and, for a branch, of its vertices)
};

double total_length(const Skeleton& s) {
  double total = 0;
  for (const auto& e : s.edges) total += (s.nodes[e[1]] - s.nodes[e[0]]).norm();
  return total;
}

// The changes small enough to be made, the least significant first (at most `limit`).
std::vector<Change> candidate_changes(const Skeleton& s, double max_branch, size_t limit) {
  const double total = total_length(s);
  const ReducedSkeleton r = reduce_skeleton(s);
  std::vector<int> owned(s.nodes.size(), 0);
  for (int x : s.vertex_node) ++owned[x];
  const double nv = double(std::max<size_t>(1, s.vertex_node.size()));
  std::vector<Change> out;
  for (const auto& c : r.chains) {
    if (c.from == c.to || !(total > 0)) continue;
    const int df = r.key_degree[c.from], dt = r.key_degree[c.to];
    const double share = c.length / total;
    if (df >= 3 && dt >= 3) {  // between two junctions: contract when short and not doubled
      const int parallel = int(std::count_if(r.chains.begin(), r.chains.end(), [&](const ReducedSkeleton::Chain& d) {
        return std::minmax(d.from, d.to) == std::minmax(c.from, c.to);
      }));
      if (parallel > 1 || share > 0.5 * max_branch) continue;
      Change ch;
      ch.join = true, ch.junction = c.nodes.front(), ch.other = c.nodes.back(), ch.significance = share;
      ch.removed.assign(c.nodes.begin() + 1, c.nodes.end() - 1);
      out.push_back(std::move(ch));
    } else if ((df == 1) != (dt == 1) && std::max(df, dt) >= 3) {  // an end branch
      Change ch;
      const bool end_first = df == 1;
      ch.end = end_first ? c.nodes.front() : c.nodes.back();
      ch.junction = end_first ? c.nodes.back() : c.nodes.front();
      for (int x : c.nodes)
        if (x != ch.junction) ch.removed.push_back(x);
      double verts = 0;
      for (int x : ch.removed) verts += owned[x];
      ch.significance = std::max(share, s.vertex_node.empty() ? 0.0 : verts / nv);
      if (ch.significance <= max_branch) out.push_back(std::move(ch));
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const Change& x, const Change& y) { return x.significance < y.significance; });
  if (out.size() > limit) out.resize(limit);
  return out;
}

// The skeleton after the given changes; `map` receives old node -> new node (-1: pruned; a merged
// node: its junction's new node), `original` new node -> the old node it stands for.
Skeleton apply_changes(const Skeleton& s, const std::vector<const Change*>& changes, std::vector<int>& map, std::vector<int>& original) {
  const int n = int(s.nodes.size());
  std::vector<int> rep(n);  // merged junctions: union-find
  std::iota(rep.begin(), rep.end(), 0);
  std::function<int(int)> find = [&](int x) { return rep[x] == x ? x : rep[x] = find(rep[x]); };
  std::vector<int> owner(n, -1);  // a removed node -> the node that takes its vertices
  std::vector<char> pruned(n, 0);
  for (const Change* c : changes) {
    if (c->join) {
      const int x = find(c->junction), y = find(c->other);
      if (x != y) rep[std::max(x, y)] = std::min(x, y);
    }
    for (int x : c->removed) owner[x] = c->junction, pruned[x] = !c->join;
  }
  auto target = [&](int x) { return find(owner[x] >= 0 ? owner[x] : x); };
  map.assign(n, -1);
  original.clear();
  Skeleton out;
  std::vector<Eigen::Vector3d> sum;
  std::vector<int> count;
  for (int i = 0; i < n; ++i)
    if (owner[i] < 0 && find(i) == i) map[i] = int(out.nodes.size()), out.nodes.push_back(s.nodes[i]), original.push_back(i);
  sum.assign(out.nodes.size(), Eigen::Vector3d::Zero());
  count.assign(out.nodes.size(), 0);
  for (int i = 0; i < n; ++i)
    if (owner[i] < 0) sum[map[find(i)]] += s.nodes[i], ++count[map[find(i)]];
  for (size_t k = 0; k < out.nodes.size(); ++k) out.nodes[k] = sum[k] / double(count[k]);  // merged junctions: their mean
  for (int i = 0; i < n; ++i)
    if (!pruned[i] && map[i] < 0) map[i] = map[target(i)];
  for (const auto& e : s.edges) {
    if (pruned[e[0]] || pruned[e[1]]) continue;
    const int x = map[target(e[0])], y = map[target(e[1])];
    if (x == y) continue;
    const std::array<int, 2> ne{std::min(x, y), std::max(x, y)};
    if (std::find(out.edges.begin(), out.edges.end(), ne) == out.edges.end()) out.edges.push_back(ne);
  }
  for (int x : s.vertex_node) out.vertex_node.push_back(map[target(x)]);
  return out;
}

// Every subset of {0..n-1} with `k` elements.
void subsets(int n, int k, std::vector<int>& current, int start, const std::function<void(const std::vector<int>&)>& visit) {
  if (int(current.size()) == k) return visit(current);
  for (int i = start; i < n; ++i) {
    current.push_back(i);
    subsets(n, k, current, i + 1, visit);
    current.pop_back();
  }
}

CommonBranching unchanged(const Skeleton& a, const Skeleton& b) {
  CommonBranching r;
  r.a = a, r.b = b;
  r.a_node.resize(a.nodes.size());
  r.b_node.resize(b.nodes.size());
  std::iota(r.a_node.begin(), r.a_node.end(), 0);
  std::iota(r.b_node.begin(), r.b_node.end(), 0);
  r.a_original = r.a_node, r.b_original = r.b_node;
  return r;
}

void record(const std::vector<const Change*>& changes, std::vector<int>& pruned, std::vector<std::pair<int, int>>& joined) {
  pruned.clear(), joined.clear();
  for (const Change* c : changes)
    if (c->join) joined.push_back({c->junction, c->other});
    else pruned.push_back(c->end);
}

}  // namespace

CommonBranching common_branching(const Skeleton& a, const Skeleton& b, double max_branch, int max_changes) {
  const std::string diff = branching_difference(a, b);
  if (diff.empty()) return unchanged(a, b);
  CommonBranching r;
  const std::vector<Change> ca = candidate_changes(a, max_branch, 14), cb = candidate_changes(b, max_branch, 14);
  std::vector<const Change*> all;  // a's changes, then b's
  for (const auto& c : ca) all.push_back(&c);
  for (const auto& c : cb) all.push_back(&c);
  // The fewest changes first; among equals, the least significance removed, then the best match.
  double best_sig = INFINITY, best_cost = INFINITY;
  for (int k = 1; k <= std::min<int>(max_changes, int(all.size())) && !std::isfinite(best_sig); ++k) {
    std::vector<int> pick;
    subsets(int(all.size()), k, pick, 0, [&](const std::vector<int>& chosen) {
      std::vector<const Change*> xa, xb;
      double sig = 0;
      for (int i : chosen) (i < int(ca.size()) ? xa : xb).push_back(all[i]), sig += all[i]->significance;
      if (sig > best_sig + 1e-9) return;
      std::vector<int> map_a, map_b, orig_a, orig_b;
      const Skeleton pa = apply_changes(a, xa, map_a, orig_a), pb = apply_changes(b, xb, map_b, orig_b);
      if (!branching_difference(pa, pb).empty()) return;
      double cost = INFINITY;
      try {
        cost = match_skeletons(pa, pb).cost;
      } catch (const InputError&) {
        return;  // same degrees, connected otherwise
      }
      if (sig >= best_sig - 1e-9 && !(cost < best_cost)) return;
      best_sig = std::min(best_sig, sig), best_cost = cost;
      r.a = pa, r.b = pb, r.a_node = map_a, r.b_node = map_b, r.a_original = orig_a, r.b_original = orig_b;
      record(xa, r.pruned_a, r.joined_a);
      record(xb, r.pruned_b, r.joined_b);
    });
  }
  if (!std::isfinite(best_sig)) {
    std::ostringstream msg;
    msg << "the skeletons' branchings differ (source vs target): " << diff << " (and removing up to " << max_changes
        << " end branches with at most " << 100 * max_branch << " % of a skeleton's length and vertices, or contracting"
        << " chains between junctions under " << 50 * max_branch << " %, does not make them equal: the major branchings differ)";
    throw InputError(msg.str());
  }
  return r;
}

}  // namespace sdm
