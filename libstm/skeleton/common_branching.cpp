#include "libstm/skeleton/common_branching.h"

#include "libstm/core/errors.h"
#include "libstm/skeleton/match_skeletons.h"

#include <cmath>
#include <functional>
#include <sstream>

namespace sdm {
namespace {

struct EndBranch {
  int end = -1, junction = -1;
  std::vector<int> removed;  // the end node and the chain's inner nodes
};

// End branches short enough to be pruned.
std::vector<EndBranch> prunable_branches(const Skeleton& s, double max_branch) {
  double total = 0;
  for (const auto& e : s.edges) total += (s.nodes[e[1]] - s.nodes[e[0]]).norm();
  const auto adj = s.adjacency();
  std::vector<EndBranch> out;
  for (size_t i = 0; i < s.nodes.size(); ++i) {
    if (adj[i].size() != 1) continue;
    EndBranch b;
    b.end = int(i);
    b.removed.push_back(int(i));
    int prev = int(i), cur = adj[i][0];
    double length = (s.nodes[cur] - s.nodes[i]).norm();
    while (adj[cur].size() == 2) {
      b.removed.push_back(cur);
      const int next = adj[cur][0] == prev ? adj[cur][1] : adj[cur][0];
      length += (s.nodes[next] - s.nodes[cur]).norm();
      prev = cur;
      cur = next;
    }
    if (adj[cur].size() < 3 || length > max_branch * total) continue;  // a bare chain, or a real limb
    b.junction = cur;
    out.push_back(std::move(b));
  }
  return out;
}

// The skeleton without the given branches; `map` receives old node -> new node (-1: removed).
Skeleton prune(const Skeleton& s, const std::vector<const EndBranch*>& branches, std::vector<int>& map) {
  std::vector<int> owner(s.nodes.size(), -1);  // removed node -> its junction
  for (const EndBranch* b : branches)
    for (int x : b->removed) owner[x] = b->junction;
  map.assign(s.nodes.size(), -1);
  Skeleton out;
  for (size_t i = 0; i < s.nodes.size(); ++i)
    if (owner[i] < 0) map[i] = int(out.nodes.size()), out.nodes.push_back(s.nodes[i]);
  for (const auto& e : s.edges)
    if (map[e[0]] >= 0 && map[e[1]] >= 0) out.edges.push_back({map[e[0]], map[e[1]]});
  for (int x : s.vertex_node) out.vertex_node.push_back(map[owner[x] >= 0 ? owner[x] : x]);
  return out;
}

std::vector<int> inverse(const std::vector<int>& map, size_t n) {
  std::vector<int> out(n, -1);
  for (size_t i = 0; i < map.size(); ++i)
    if (map[i] >= 0) out[map[i]] = int(i);
  return out;
}

// Every subset of `items` with `k` elements.
void subsets(int n, int k, std::vector<int>& current, int start, const std::function<void(const std::vector<int>&)>& visit) {
  if (int(current.size()) == k) return visit(current);
  for (int i = start; i < n; ++i) {
    current.push_back(i);
    subsets(n, k, current, i + 1, visit);
    current.pop_back();
  }
}

}  // namespace

CommonBranching common_branching(const Skeleton& a, const Skeleton& b, double max_branch, int max_pruned) {
  CommonBranching r;
  const std::string diff = branching_difference(a, b);
  if (diff.empty()) {
    r.a = a, r.b = b;
    for (size_t i = 0; i < a.nodes.size(); ++i) r.a_node.push_back(int(i));
    for (size_t i = 0; i < b.nodes.size(); ++i) r.b_node.push_back(int(i));
    r.a_original = r.a_node, r.b_original = r.b_node;
    return r;
  }
  const std::vector<EndBranch> ca = prunable_branches(a, max_branch), cb = prunable_branches(b, max_branch);
  // The fewest removals first; among equals, the pruning whose match fits best.
  double best = INFINITY;
  for (int total = 1; total <= max_pruned && !std::isfinite(best); ++total)
    for (int ra = 0; ra <= total; ++ra) {
      const int rb = total - ra;
      std::vector<int> sa, sb;
      subsets(int(ca.size()), ra, sa, 0, [&](const std::vector<int>& pick_a) {
        std::vector<const EndBranch*> ba;
        for (int i : pick_a) ba.push_back(&ca[i]);
        std::vector<int> map_a;
        const Skeleton pa = prune(a, ba, map_a);
        subsets(int(cb.size()), rb, sb, 0, [&](const std::vector<int>& pick_b) {
          std::vector<const EndBranch*> bb;
          for (int i : pick_b) bb.push_back(&cb[i]);
          std::vector<int> map_b;
          const Skeleton pb = prune(b, bb, map_b);
          if (!branching_difference(pa, pb).empty()) return;
          double cost = INFINITY;
          try {
            cost = match_skeletons(pa, pb).cost;
          } catch (const InputError&) {
            return;  // same degrees, connected otherwise
          }
          if (!(cost < best)) return;
          best = cost;
          r.a = pa, r.b = pb, r.a_node = map_a, r.b_node = map_b;
          r.pruned_a.clear(), r.pruned_b.clear();
          for (const auto* x : ba) r.pruned_a.push_back(x->end);
          for (const auto* x : bb) r.pruned_b.push_back(x->end);
        });
      });
    }
  if (!std::isfinite(best)) {
    std::ostringstream msg;
    msg << "the skeletons' branchings differ (source vs target): " << diff << " (and removing up to " << max_pruned
        << " end branches shorter than " << 100 * max_branch << " % of a skeleton's length does not make them equal)";
    throw InputError(msg.str());
  }
  r.a_original = inverse(r.a_node, r.a.nodes.size());
  r.b_original = inverse(r.b_node, r.b.nodes.size());
  return r;
}

}  // namespace sdm
