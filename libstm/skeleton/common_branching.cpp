#include "libstm/skeleton/common_branching.h"

#include "libstm/core/errors.h"
#include "libstm/skeleton/match_skeletons.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numeric>
#include <sstream>

namespace sdm {
namespace {

// One reduction of a skeleton: an end branch pruned (its nodes go to `junction`), a chain
// between two junctions contracted (its inner nodes and `other` merge into `junction`), or a
// branch slid from `junction` to the neighbouring junction `other`: its nodes up to `attach` (the
// one nearest `other`) go, their vertices to the nearest node of the chain between the junctions,
// and `attach` is joined to `other` (edge `dropped` is cut).
struct Change {
  bool join = false, slide = false;
  int end = -1, junction = -1, other = -1, attach = -1;
  std::array<int, 2> dropped{-1, -1};
  std::vector<int> removed;  // pruned: the end node and the chain's inner nodes; joined: the inner nodes
  std::vector<int> owner;    // slid: per removed node, the node that takes its vertices
  double significance = 0;   // share of the skeleton's length (and, for a branch, of its vertices)
};

double total_length(const Skeleton& s) {
  double total = 0;
  for (const auto& e : s.edges) total += (s.nodes[e[1]] - s.nodes[e[0]]).norm();
  return total;
}

// An end branch's significance: the larger of its share of the skeleton's total length and of the
// vertices its nodes other than `junction` own (`owned` per node).
double end_significance(const Skeleton& s, const ReducedSkeleton::Chain& c, int junction, const std::vector<int>& owned, double total) {
  double verts = 0;
  for (int x : c.nodes)
    if (x != junction) verts += owned[x];
  return std::max(c.length / total, s.vertex_node.empty() ? 0.0 : verts / double(s.vertex_node.size()));
}

// The changes small enough to be made, the least significant first (at most `limit`).
std::vector<Change> candidate_changes(const Skeleton& s, double max_branch, size_t limit) {
  const double total = total_length(s);
  const ReducedSkeleton r = reduce_skeleton(s);
  std::vector<int> owned(s.nodes.size(), 0);
  for (int x : s.vertex_node) ++owned[x];
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
      ch.significance = end_significance(s, c, ch.junction, owned, total);
      if (ch.significance <= max_branch) out.push_back(std::move(ch));
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const Change& x, const Change& y) { return x.significance < y.significance; });
  if (out.size() > limit) out.resize(limit);
  return out;
}

// The slides small enough to be tried, the least significant first (at most `limit`): for every
// chain S between two junctions J and K (no other chain joining them) and every other chain A at
// J that is not an end branch small enough to prune (max_branch, as candidate_changes), A slid from
// J to K (and the same from K to J). A's nodes from J up to the one nearest K go; the share of the
// skeleton's length they span is the slide's significance (at most max_share).
std::vector<Change> candidate_slides(const Skeleton& s, double max_share, double max_branch, size_t limit) {
  const double total = total_length(s);
  const ReducedSkeleton r = reduce_skeleton(s);
  std::vector<Change> out;
  if (!(total > 0)) return out;
  std::vector<int> owned(s.nodes.size(), 0);
  for (int x : s.vertex_node) ++owned[x];
  // An end branch small enough to be pruned (candidate_changes) does not slide: a thumb forked off
  // a hand, slid along the arm to the shoulder, became a head where the extraction had lost it.
  auto small_end = [&](const ReducedSkeleton::Chain& A) {
    if ((r.key_degree[A.from] == 1) == (r.key_degree[A.to] == 1)) return false;  // not an end branch
    const int junction = r.key_degree[A.from] == 1 ? A.nodes.back() : A.nodes.front();
    return end_significance(s, A, junction, owned, total) <= max_branch;
  };
  for (const auto& S : r.chains) {
    if (S.from == S.to || r.key_degree[S.from] < 3 || r.key_degree[S.to] < 3) continue;
    const int parallel = int(std::count_if(r.chains.begin(), r.chains.end(), [&](const ReducedSkeleton::Chain& d) {
      return std::minmax(d.from, d.to) == std::minmax(S.from, S.to);
    }));
    if (parallel > 1) continue;
    for (int side = 0; side < 2; ++side) {
      const int J = side ? S.nodes.back() : S.nodes.front(), K = side ? S.nodes.front() : S.nodes.back();
      for (const auto& A : r.chains) {
        if (&A == &S || A.from == A.to || (A.nodes.front() != J && A.nodes.back() != J) || small_end(A)) continue;
        std::vector<int> walk = A.nodes;  // from J outwards
        if (walk.front() != J) std::reverse(walk.begin(), walk.end());
        size_t best = 1;
        for (size_t i = 1; i < walk.size(); ++i)
          if ((s.nodes[walk[i]] - s.nodes[K]).norm() < (s.nodes[walk[best]] - s.nodes[K]).norm()) best = i;
        Change ch;
        ch.slide = true, ch.junction = J, ch.other = K, ch.attach = walk[best], ch.dropped = {walk[best - 1], walk[best]};
        for (size_t i = 1; i < best; ++i) {
          ch.removed.push_back(walk[i]);
          int near = S.nodes.front();
          for (int x : S.nodes)
            if ((s.nodes[x] - s.nodes[walk[i]]).norm() < (s.nodes[near] - s.nodes[walk[i]]).norm()) near = x;
          ch.owner.push_back(near);
        }
        for (size_t i = 1; i <= best; ++i) ch.significance += (s.nodes[walk[i]] - s.nodes[walk[i - 1]]).norm() / total;
        if (ch.significance <= max_share) out.push_back(std::move(ch));
      }
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
    for (size_t i = 0; i < c->removed.size(); ++i) owner[c->removed[i]] = c->slide ? c->owner[i] : c->junction, pruned[c->removed[i]] = !c->join;
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
  auto add_edge = [&](int a, int b) {
    const int x = map[target(a)], y = map[target(b)];
    if (x == y || x < 0 || y < 0) return;
    const std::array<int, 2> ne{std::min(x, y), std::max(x, y)};
    if (std::find(out.edges.begin(), out.edges.end(), ne) == out.edges.end()) out.edges.push_back(ne);
  };
  auto dropped = [&](const std::array<int, 2>& e) {
    for (const Change* c : changes)
      if (c->slide && std::minmax(c->dropped[0], c->dropped[1]) == std::minmax(e[0], e[1])) return true;
    return false;
  };
  for (const auto& e : s.edges)
    if (!pruned[e[0]] && !pruned[e[1]] && !dropped(e)) add_edge(e[0], e[1]);
  for (const Change* c : changes)
    if (c->slide) add_edge(c->attach, c->other);
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

void record(const std::vector<const Change*>& changes, std::vector<int>& pruned, std::vector<std::pair<int, int>>& joined,
            std::vector<std::array<int, 3>>& slid) {
  pruned.clear(), joined.clear(), slid.clear();
  for (const Change* c : changes)
    if (c->join) joined.push_back({c->junction, c->other});
    else if (c->slide) slid.push_back({c->attach, c->junction, c->other});
    else pruned.push_back(c->end);
}

// The given changes applied to both skeletons, when that makes their branchings equal and
// matchable: the result, its match's cost and length disagreement (length_disagreement).
struct Tried {
  bool ok = false;
  CommonBranching r;
  double cost = INFINITY, disagreement = INFINITY;
};
Tried try_changes(const Skeleton& a, const Skeleton& b, const std::vector<const Change*>& xa, const std::vector<const Change*>& xb) {
  Tried t;
  std::vector<int> map_a, map_b, orig_a, orig_b;
  const Skeleton pa = apply_changes(a, xa, map_a, orig_a), pb = apply_changes(b, xb, map_b, orig_b);
  if (!branching_difference(pa, pb).empty()) return t;
  try {
    const SkeletonMatch m = match_skeletons(pa, pb);
    t.cost = m.cost, t.disagreement = length_disagreement(m);
    // The best match on shape and pose may pair a head with an arm where another pairing agrees:
    // the branching is as plausible as its most plausible match (match_candidates keeps those).
    if (t.disagreement > 1.5)
      for (const SkeletonMatch& c : match_candidates(pa, pb, {}, 4)) t.disagreement = std::min(t.disagreement, length_disagreement(c));
  } catch (const InputError&) {
    return t;  // same degrees, connected otherwise
  }
  t.ok = true;
  t.r.a = pa, t.r.b = pb, t.r.a_node = map_a, t.r.b_node = map_b, t.r.a_original = orig_a, t.r.b_original = orig_b;
  record(xa, t.r.pruned_a, t.r.joined_a, t.r.slid_a);
  record(xb, t.r.pruned_b, t.r.joined_b, t.r.slid_b);
  t.r.length_disagreement = t.disagreement;
  return t;
}

// a's changes, then b's, as one list (an index below ca.size() is a's).
std::vector<const Change*> both(const std::vector<Change>& ca, const std::vector<Change>& cb) {
  std::vector<const Change*> all;
  for (const auto& c : ca) all.push_back(&c);
  for (const auto& c : cb) all.push_back(&c);
  return all;
}

// Prunes and joins only: the fewest changes, then the least significance removed, then the lowest
// match cost. Not ok when none of at most max_changes makes the branchings equal.
Tried reduce_by_pruning(const Skeleton& a, const Skeleton& b, const std::vector<Change>& ca, const std::vector<Change>& cb, int max_changes) {
  const std::vector<const Change*> all = both(ca, cb);
  Tried best;
  double best_sig = INFINITY;
  for (int k = 1; k <= std::min<int>(max_changes, int(all.size())) && !best.ok; ++k) {
    std::vector<int> pick;
    subsets(int(all.size()), k, pick, 0, [&](const std::vector<int>& chosen) {
      std::vector<const Change*> xa, xb;
      double sig = 0;
      for (int i : chosen) (i < int(ca.size()) ? xa : xb).push_back(all[i]), sig += all[i]->significance;
      if (sig > best_sig + 1e-9) return;
      Tried t = try_changes(a, b, xa, xb);
      if (!t.ok || (sig >= best_sig - 1e-9 && !(t.cost < best.cost))) return;
      best_sig = std::min(best_sig, sig), best = std::move(t);
    });
  }
  return best;
}

// Whether a slide's branch hangs from a junction of the reduced skeleton `red` (`map`: the given
// skeleton's nodes -> red's): prunes taken with it may leave its new junction with one other
// branch, and the slid branch would then continue that one instead of meeting the core (a jittered
// FAUST 024's head slid onto a hand whose two finger prongs were pruned, to match a target skeleton
// that had lost its head).
bool slid_onto_junction(const Skeleton& red, const std::vector<int>& map, const Change& slide) {
  const int at = slide.other >= 0 && size_t(slide.other) < map.size() ? map[size_t(slide.other)] : -1;
  return at >= 0 && red.degrees()[size_t(at)] >= 3;
}

// One slide (in either skeleton) with at most two prunes or joins: among the results whose
// matched chains agree in length (length_disagreement at most `plausible`), the fewest changes,
// then the lowest disagreement. A slide must land on a junction (slid_onto_junction) and leave its
// skeleton a core of at least kCoreShare: Homer's medial skeleton (alecjacobson/common-3d-test-
// models) hangs his right arm from the belly 1 % of its length from his hips, and sliding the left
// arm there too, to agree with FAUST 024, left every limb on two junctions that close, whose
// attachments then go unmeasured (register_bodies), and the match upside down went through.
Tried reduce_with_slide(const Skeleton& a, const Skeleton& b, const std::vector<Change>& ca, const std::vector<Change>& cb,
                        const std::vector<Change>& sa, const std::vector<Change>& sb, double plausible) {
  const std::vector<const Change*> all = both(ca, cb);
  Tried best;
  size_t best_changes = SIZE_MAX;
  for (int side = 0; side < 2; ++side)
    for (const Change& slide : side ? sb : sa)
      for (int k = 0; k <= std::min(2, int(all.size())); ++k) {
        std::vector<int> pick;
        subsets(int(all.size()), k, pick, 0, [&](const std::vector<int>& chosen) {
          std::vector<const Change*> xa, xb;
          (side ? xb : xa).push_back(&slide);
          for (int i : chosen) (i < int(ca.size()) ? xa : xb).push_back(all[i]);
          const size_t n = xa.size() + xb.size();
          if (n > best_changes) return;
          Tried t = try_changes(a, b, xa, xb);
          if (!t.ok || t.disagreement > plausible || (n == best_changes && !(t.disagreement < best.disagreement))) return;
          if (!slid_onto_junction(side ? t.r.b : t.r.a, side ? t.r.b_node : t.r.a_node, slide)) return;
          if (core_share(reduce_skeleton(side ? t.r.b : t.r.a)) < kCoreShare) return;  // joined the core up
          best_changes = n, best = std::move(t);
        });
      }
  return best;
}

}  // namespace

CommonBranching common_branching(const Skeleton& a, const Skeleton& b, double max_branch, int max_changes, double plausible) {
  const std::string diff = branching_difference(a, b);
  const std::vector<Change> ca = candidate_changes(a, max_branch, 14), cb = candidate_changes(b, max_branch, 14);
  Tried first = diff.empty() ? try_changes(a, b, {}, {}) : reduce_by_pruning(a, b, ca, cb, max_changes);
  if (first.ok && first.disagreement <= plausible) return first.r;
  // The matched chains disagree in length (or no pruning makes the branchings equal): an
  // extraction may have hung a branch from the neighbouring junction (an arm from the pelvis,
  // its chain running down the side of a flat torso).
  // A skeleton whose junctions nearly coincide (its core under kCoreShare of its length: the TOSCA
  // gorilla's medial skeleton joins head, arms and legs within 0.5 %) says nothing about which
  // branch hangs from which junction, so the other is not slid to agree with it.
  const bool a_slides = core_share(reduce_skeleton(b)) >= kCoreShare, b_slides = core_share(reduce_skeleton(a)) >= kCoreShare;
  const std::vector<Change> sa = a_slides ? candidate_slides(a, 3 * max_branch, max_branch, 8) : std::vector<Change>(),
                            sb = b_slides ? candidate_slides(b, 3 * max_branch, max_branch, 8) : std::vector<Change>();
  Tried slid = reduce_with_slide(a, b, ca, cb, sa, sb, plausible);
  if (slid.ok) return slid.r;
  if (first.ok) return first.r;
  if (diff.empty()) return unchanged(a, b);  // connected otherwise: match_skeletons names it
  std::ostringstream msg;
  msg << "the skeletons' branchings differ (source vs target): " << diff << " (and removing up to " << max_changes
      << " end branches with at most " << 100 * max_branch << " % of a skeleton's length and vertices, or contracting"
      << " chains between junctions under " << 50 * max_branch << " %, does not make them equal: the major branchings differ)";
  throw InputError(msg.str());
}

}  // namespace sdm
