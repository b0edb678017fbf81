#include "libstm/skeleton/exchange_branches.h"

#include <algorithm>
#include <utility>

namespace sdm {

namespace {

// A chain leaving a junction: the node where it stops (the first of degree other than 2) and its
// length.
struct Chain {
  int last = -1;
  double length = 0;
};

Chain walk(const Skeleton& s, const std::vector<std::vector<int>>& adj, int junction, int first) {
  Chain c{first, (s.nodes[size_t(first)] - s.nodes[size_t(junction)]).norm()};
  int prev = junction;
  while (adj[size_t(c.last)].size() == 2) {
    const int next = adj[size_t(c.last)][0] == prev ? adj[size_t(c.last)][1] : adj[size_t(c.last)][0];
    c.length += (s.nodes[size_t(next)] - s.nodes[size_t(c.last)]).norm();
    prev = c.last, c.last = next;
    if (c.last == junction) break;  // a loop back to the junction: not an end branch
  }
  return c;
}

// The edge (a, b) in either order replaced by (a, c).
void reattach(Skeleton& s, int a, int b, int c) {
  for (auto& e : s.edges)
    if ((e[0] == a && e[1] == b) || (e[0] == b && e[1] == a)) {
      e = {c, b};
      return;
    }
}

}  // namespace

std::vector<Skeleton> exchanged_branches(const Skeleton& s, double max_inner, double max_ratio) {
  // Every single exchange: junctions j < k, the first nodes a (of j's branch) and b (of k's).
  struct Exchange {
    int j, a, k, b;
  };
  std::vector<Exchange> single;
  const std::vector<std::vector<int>> adj = s.adjacency();
  double total = 0;
  for (const auto& e : s.edges) total += (s.nodes[size_t(e[0])] - s.nodes[size_t(e[1])]).norm();
  for (int j = 0; j < int(adj.size()); ++j) {
    if (adj[size_t(j)].size() < 3) continue;
    for (int n : adj[size_t(j)]) {
      const Chain inner = walk(s, adj, j, n);
      const int k = inner.last;
      if (k <= j || adj[size_t(k)].size() < 3 || inner.length > max_inner * total) continue;
      // End branches at j and at k (the inner chain itself excluded).
      for (int a : adj[size_t(j)]) {
        const Chain ea = walk(s, adj, j, a);
        if (a == n || adj[size_t(ea.last)].size() != 1) continue;
        for (int b : adj[size_t(k)]) {
          const Chain eb = walk(s, adj, k, b);
          if (eb.last == j || adj[size_t(eb.last)].size() != 1 || ea.last == eb.last) continue;
          const double longer = std::max(ea.length, eb.length), shorter = std::min(ea.length, eb.length);
          if (longer <= max_ratio * shorter) single.push_back({j, a, k, b});
        }
      }
    }
  }
  // Every set of exchanges on disjoint junction pairs (both shoulders and both hips of one body can
  // be split the other way round at once), at most 2^6 - 1 of them. Exchanges sharing a junction
  // would move one branch twice.
  std::vector<Skeleton> out;
  const size_t n = std::min<size_t>(single.size(), 6);
  for (unsigned mask = 1; mask < (1u << n); ++mask) {
    Skeleton v = s;
    std::vector<int> used;
    bool clash = false;
    for (size_t x = 0; x < n && !clash; ++x) {
      if (!(mask >> x & 1u)) continue;
      const Exchange& e = single[x];
      clash = std::find(used.begin(), used.end(), e.j) != used.end() || std::find(used.begin(), used.end(), e.k) != used.end();
      used.push_back(e.j), used.push_back(e.k);
      reattach(v, e.j, e.a, e.k);
      reattach(v, e.k, e.b, e.j);
    }
    if (!clash) out.push_back(std::move(v));
  }
  return out;
}

}  // namespace sdm
