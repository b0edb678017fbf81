#include "libstm/skeleton/match_skeletons.h"

#include "libstm/core/errors.h"
#include "libstm/geometry/differential_geometry.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <sstream>

namespace sdm {
namespace {

std::vector<int> component_labels(const Skeleton& s) {
  std::vector<int> label(s.nodes.size(), -1);
  const auto adj = s.adjacency();
  int c = 0;
  for (size_t i = 0; i < s.nodes.size(); ++i) {
    if (label[i] >= 0) continue;
    std::vector<int> stack{int(i)};
    label[i] = c;
    while (!stack.empty()) {
      int x = stack.back();
      stack.pop_back();
      for (int y : adj[x])
        if (label[y] < 0) label[y] = c, stack.push_back(y);
    }
    ++c;
  }
  return label;
}

// Point at arc-length fraction f along a chain (reversed: from its end).
Eigen::Vector3d chain_point(const Skeleton& s, const ReducedSkeleton::Chain& c, double f, bool reversed) {
  if (reversed) f = 1 - f;
  double total = 0;  // measured here: `s` may be a rescaled copy of the skeleton c was made from
  for (size_t k = 0; k + 1 < c.nodes.size(); ++k) total += (s.nodes[c.nodes[k + 1]] - s.nodes[c.nodes[k]]).norm();
  double target = f * total, run = 0;
  for (size_t k = 0; k + 1 < c.nodes.size(); ++k) {
    const Eigen::Vector3d p = s.nodes[c.nodes[k]], q = s.nodes[c.nodes[k + 1]];
    const double l = (q - p).norm();
    if (run + l >= target || k + 2 == c.nodes.size()) return l > 0 ? p + (q - p) * std::clamp((target - run) / l, 0.0, 1.0) : p;
    run += l;
  }
  return s.nodes[c.nodes.front()];
}

// Positions centred on the node centroid and scaled to unit RMS radius: pose and size neutral.
std::vector<Eigen::Vector3d> normalised_nodes(const Skeleton& s) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : s.nodes) c += p;
  c /= double(std::max<size_t>(1, s.nodes.size()));
  double r2 = 0;
  for (const auto& p : s.nodes) r2 += (p - c).squaredNorm();
  const double scale = r2 > 0 ? 1.0 / std::sqrt(r2 / double(s.nodes.size())) : 1.0;
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : s.nodes) out.push_back((p - c) * scale);
  return out;
}

// Best rotation (no reflection) taking points a onto points b, and the mean squared residual.
// nearest_rotation of sum b a^T replaced a local SVD of sum a b^T (R = V D U^T): the rotations
// differ in the last bits (at most 2e-15 over 10000 random point sets), the demo's outputs not at all.
double kabsch(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, Eigen::Matrix3d& R) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < a.size(); ++i) H += b[i] * a[i].transpose();
  R = nearest_rotation(H);
  double e = 0;
  for (size_t i = 0; i < a.size(); ++i) e += (R * a[i] - b[i]).squaredNorm();
  return a.empty() ? 0.0 : e / double(a.size());
}

// length_disagreement of a chain map between two reduced skeletons.
double chain_disagreement(const ReducedSkeleton& a, const ReducedSkeleton& b, const std::vector<std::pair<int, bool>>& chain_map,
                          double min_share) {
  double total_a = 0, total_b = 0, worst = 1;
  for (const auto& c : a.chains) total_a += c.length;
  for (const auto& c : b.chains) total_b += c.length;
  if (!(total_a > 0) || !(total_b > 0) || chain_map.size() != a.chains.size()) return worst;
  for (size_t c = 0; c < a.chains.size(); ++c) {
    if (a.key_degree[a.chains[c].from] != 1 && a.key_degree[a.chains[c].to] != 1) continue;  // between junctions
    const double sa = a.chains[c].length / total_a, sb = b.chains[chain_map[c].first].length / total_b;
    if (std::max(sa, sb) < min_share) continue;
    worst = std::max(worst, std::max(sa, sb) / std::max(std::min(sa, sb), 1e-12));
  }
  return worst;
}

}  // namespace

ReducedSkeleton reduce_skeleton(const Skeleton& s) {
  ReducedSkeleton r;
  const std::vector<int> deg = s.degrees();
  std::vector<std::vector<std::pair<int, int>>> adj(s.nodes.size());  // (neighbour, edge)
  for (size_t e = 0; e < s.edges.size(); ++e) {
    adj[s.edges[e][0]].push_back({s.edges[e][1], int(e)});
    adj[s.edges[e][1]].push_back({s.edges[e][0], int(e)});
  }
  std::vector<int> key_of(s.nodes.size(), -1);
  for (size_t i = 0; i < s.nodes.size(); ++i)
    if (deg[i] != 2) key_of[i] = 0;
  // Pure cycles: no node of degree != 2; the node farthest from the component's centre is key.
  const std::vector<int> label = component_labels(s);
  const int ncomp = label.empty() ? 0 : *std::max_element(label.begin(), label.end()) + 1;
  for (int c = 0; c < ncomp; ++c) {
    bool has_key = false;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    int n = 0;
    for (size_t i = 0; i < s.nodes.size(); ++i)
      if (label[i] == c) has_key |= key_of[i] >= 0, centre += s.nodes[i], ++n;
    if (has_key) continue;
    centre /= n;
    int best = -1;
    for (size_t i = 0; i < s.nodes.size(); ++i) {
      if (label[i] != c) continue;
      if (best < 0) {
        best = int(i);
        continue;
      }
      const double di = (s.nodes[i] - centre).norm(), db = (s.nodes[best] - centre).norm();
      const auto& p = s.nodes[i];
      const auto& q = s.nodes[best];
      if (di > db + 1e-12 || (std::abs(di - db) <= 1e-12 && std::tie(p.x(), p.y(), p.z()) > std::tie(q.x(), q.y(), q.z())))
        best = int(i);
    }
    key_of[best] = 0;
  }
  for (size_t i = 0; i < s.nodes.size(); ++i)
    if (key_of[i] >= 0) {
      key_of[i] = int(r.keys.size());
      r.keys.push_back(int(i));
      r.key_degree.push_back(deg[i]);
    }
  std::vector<char> used(s.edges.size(), 0);
  for (int k : r.keys) {
    for (auto [first, first_edge] : adj[k]) {
      if (used[first_edge]) continue;
      ReducedSkeleton::Chain c;
      c.from = key_of[k];
      c.nodes.push_back(k);
      int prev_edge = first_edge, cur = first;
      for (;;) {
        used[prev_edge] = 1;
        c.edges.push_back(prev_edge);
        c.length += (s.nodes[cur] - s.nodes[c.nodes.back()]).norm();
        c.nodes.push_back(cur);
        if (key_of[cur] >= 0) break;
        const auto& nb = adj[cur];
        const auto next = nb[0].second == prev_edge ? nb[1] : nb[0];
        prev_edge = next.second;
        cur = next.first;
      }
      c.to = key_of[cur];
      r.chains.push_back(std::move(c));
    }
  }
  return r;
}

double core_share(const ReducedSkeleton& r) {
  double core = 0, total = 0;
  for (const auto& c : r.chains) {
    total += c.length;
    if (r.key_degree[c.from] >= 3 && r.key_degree[c.to] >= 3) core += c.length;
  }
  return total > 0 ? core / total : 0;
}

std::string branching_difference(const Skeleton& a, const Skeleton& b) {
  auto junctions = [](const Skeleton& s) {
    std::vector<int> d;
    for (int x : s.degrees())
      if (x >= 3) d.push_back(x);
    std::sort(d.rbegin(), d.rend());
    return d;
  };
  auto list = [](const std::vector<int>& v) {
    std::ostringstream o;
    o << '[';
    for (size_t i = 0; i < v.size(); ++i) o << (i ? ", " : "") << v[i];
    o << ']';
    return o.str();
  };
  std::vector<std::string> diffs;
  if (a.components() != b.components())
    diffs.push_back("connected parts " + std::to_string(a.components()) + " vs " + std::to_string(b.components()));
  if (junctions(a) != junctions(b)) diffs.push_back("junction degrees " + list(junctions(a)) + " vs " + list(junctions(b)));
  if (a.end_nodes() != b.end_nodes())
    diffs.push_back("ends " + std::to_string(a.end_nodes()) + " vs " + std::to_string(b.end_nodes()));
  if (a.cycles() != b.cycles()) diffs.push_back("cycles " + std::to_string(a.cycles()) + " vs " + std::to_string(b.cycles()));
  std::string out;
  for (const auto& d : diffs) out += (out.empty() ? "" : "; ") + d;
  return out;
}

namespace {

using ChainsBetween = std::map<std::pair<int, int>, std::vector<int>>;

// Chains between each pair of keys (the pair ordered).
ChainsBetween chains_between(const ReducedSkeleton& r) {
  ChainsBetween out;
  for (size_t c = 0; c < r.chains.size(); ++c) out[std::minmax(r.chains[c].from, r.chains[c].to)].push_back(int(c));
  return out;
}

int count_between(const ChainsBetween& M, int i, int j) {
  auto it = M.find(std::minmax(i, j));
  return it == M.end() ? 0 : int(it->second.size());
}

// The --match pairs in key indices: forced[key of a] = key of b, -1 where free.
std::vector<int> forced_keys(const SkeletonMatch& m, const std::vector<std::pair<int, int>>& fixed) {
  std::vector<int> forced(m.a.keys.size(), -1);
  for (auto [na, nb] : fixed) {
    auto ka = std::find(m.a.keys.begin(), m.a.keys.end(), na), kb = std::find(m.b.keys.begin(), m.b.keys.end(), nb);
    if (ka == m.a.keys.end() || kb == m.b.keys.end())
      throw InputError("--match " + std::to_string(na) + "=" + std::to_string(nb) +
                       ": both must be junction or end nodes of their skeletons");
    forced[ka - m.a.keys.begin()] = int(kb - m.b.keys.begin());
  }
  return forced;
}

// Assignment order: breadth first from the key of highest degree, so that neighbours are
// assigned early and the adjacency counts prune.
std::vector<int> assignment_order(const ReducedSkeleton& a) {
  const int nk = int(a.keys.size());
  std::vector<int> order;
  std::vector<char> seen(nk, 0);
  std::vector<int> idx(nk);
  std::iota(idx.begin(), idx.end(), 0);
  std::stable_sort(idx.begin(), idx.end(), [&](int x, int y) { return a.key_degree[x] > a.key_degree[y]; });
  for (int start : idx) {
    if (seen[start]) continue;
    std::vector<int> queue{start};
    seen[start] = 1;
    for (size_t q = 0; q < queue.size(); ++q) {
      order.push_back(queue[q]);
      for (const auto& c : a.chains) {
        int other = c.from == queue[q] ? c.to : c.to == queue[q] ? c.from : -1;
        if (other >= 0 && !seen[other]) seen[other] = 1, queue.push_back(other);
      }
    }
  }
  return order;
}

// The search over key assignments (isomorphisms of the reduced graphs), each scored by geometry.
//
// Score: shape + kLengths * lengths + pose. `shape` is pose-invariant (residual after the best
// rotation of chain samples, plus the relative chain lengths); `lengths` (the relative chain
// lengths again) is also articulation-invariant and counts kLengths times more: a head is a short
// chain, an arm a long one, however the limbs are posed (FAUST 007 -> 024: 0.004 for the right
// match, 0.029 for head <-> raised arm, whose rigid and pose residuals are lower). `pose` is the
// residual in the models' own pose when they share their orientation; shape alone cannot tell
// near-symmetric branches apart once the skeletons carry an extraction's noise (the ypsilon's
// three arms, left and right legs), and a bent limb raises the true match's shape cost above a
// relabelled one's (bent ypsilon: 0.16 against 0.04) while the pose tells them apart (0.16 against
// 1.08). When the caller does not know the orientations to agree (same_orientation false: a model
// turned around), `pose` is the residual after the rotation
// that best aligns the candidate's cores (the junctions and the first 6 % of the skeleton's length
// along their chains: the torso, which articulation hardly moves); left and right of a near-planar
// torso differ by a half turn about the spine, and the core-aligned limbs (knees forward, the
// head's tilt) tell them apart: FAUST 007 -> 024 turned, 0.47 for the right match against 0.52
// with left and right swapped. Ties go to the smaller shape cost. --match pins branches where
// this is not enough. Why the orientation is not guessed here: a human turned by a half turn is
// nearly its own mirror with left and right swapped, so the candidate best on shape + own pose
// is the swapped one with a small rotation (23.5 degrees on FAUST 007 -> 024 turned), while on
// the bent ypsilon the core alignment prefers a relabelling rotated by 120 degrees; no threshold on
// either rotation separated the two. The caller (a registration) knows better.
class Matcher {
 public:
  Matcher(SkeletonMatch& m, const Skeleton& sa, const Skeleton& sb, std::vector<int> forced, bool same_orientation);
  void assign(size_t depth);
  double best_total() const { return best_total_; }
  double second() const { return second_; }

 private:
  bool consistent(int i, int c, size_t depth) const;
  std::vector<std::pair<int, bool>> pair_chains() const;
  void evaluate();

  static constexpr long kLimit = 2000000;  // isomorphisms examined at most
  const bool same_orientation_;
  SkeletonMatch& m_;
  const ChainsBetween between_a_, between_b_;
  const std::vector<int> forced_, order_;
  const int nk_;
  Skeleton na_, nb_;  // the skeletons with normalised positions (normalised_nodes)
  double total_a_ = 0, total_b_ = 0;  // total chain lengths
  std::vector<int> map_;
  std::vector<char> taken_;
  struct Candidate {
    std::vector<int> map;
    std::vector<std::pair<int, bool>> chains;
    Eigen::Matrix3d rotation;
    double lengths, shape, pose, core_pose;
  };
  std::vector<Candidate> kept_;  // every candidate (the 10000 best on shape + pose of a huge search)
  double best_total_ = INFINITY, second_ = INFINITY;
  double core_pose(const std::vector<Eigen::Vector3d>& A, const std::vector<Eigen::Vector3d>& B,
                   const std::vector<std::pair<int, bool>>& chain_map) const;

 public:
  static constexpr double kLengths = 4;              // weight of the relative chain lengths
  static constexpr double kPlausible = 3;            // length_disagreement of a plausible candidate
  double disagreement(const Candidate& c) const;
  void choose();
  // Up to `count` candidates with distinct key maps: the best in the models' own orientation, then
  // the best after aligning their cores, then the next by that score.
  std::vector<SkeletonMatch> alternatives(size_t count) const;
};

Matcher::Matcher(SkeletonMatch& m, const Skeleton& sa, const Skeleton& sb, std::vector<int> forced, bool same_orientation)
    : same_orientation_(same_orientation), m_(m), between_a_(chains_between(m.a)), between_b_(chains_between(m.b)), forced_(std::move(forced)),
      order_(assignment_order(m.a)), nk_(int(m.a.keys.size())), na_(sa), nb_(sb), map_(nk_, -1), taken_(nk_, 0) {
  for (const auto& c : m.a.chains) total_a_ += c.length;
  for (const auto& c : m.b.chains) total_b_ += c.length;
  na_.nodes = normalised_nodes(sa);
  nb_.nodes = normalised_nodes(sb);
}

// Key c of b can stand for key i of a (assigned at `depth`): same degree, as forced, and as many
// chains to itself and to every key assigned before.
bool Matcher::consistent(int i, int c, size_t depth) const {
  if (taken_[c] || m_.b.key_degree[c] != m_.a.key_degree[i]) return false;
  if (forced_[i] >= 0 && forced_[i] != c) return false;
  bool ok = count_between(between_a_, i, i) == count_between(between_b_, c, c);
  for (size_t d = 0; d < depth && ok; ++d) {
    const int k = order_[d];
    ok = count_between(between_a_, i, k) == count_between(between_b_, c, map_[k]);
  }
  return ok;
}

void Matcher::assign(size_t depth) {
  if (m_.candidates >= kLimit) return;
  if (depth == order_.size()) return evaluate();
  const int i = order_[depth];
  for (int c = 0; c < nk_; ++c) {
    if (!consistent(i, c, depth)) continue;
    map_[i] = c;
    taken_[c] = 1;
    assign(depth + 1);
    taken_[c] = 0;
    map_[i] = -1;
  }
}

// Chains of a -> (chain of b, reversed) under the current key assignment: parallel chains (same
// two keys) paired by the permutation closest in relative length, loops directed by geometry.
std::vector<std::pair<int, bool>> Matcher::pair_chains() const {
  std::vector<std::pair<int, bool>> chain_map(m_.a.chains.size(), {-1, false});
  for (const auto& [key, list_a] : between_a_) {
    const auto& list_b = between_b_.at(std::minmax(map_[key.first], map_[key.second]));
    std::vector<int> perm(list_b.begin(), list_b.end());
    double best_perm = INFINITY;
    std::vector<int> best_p;
    std::sort(perm.begin(), perm.end());
    do {
      double e = 0;
      for (size_t k = 0; k < list_a.size(); ++k) {
        const double d = m_.a.chains[list_a[k]].length / total_a_ - m_.b.chains[perm[k]].length / total_b_;
        e += d * d;
      }
      if (e < best_perm) best_perm = e, best_p = perm;
    } while (std::next_permutation(perm.begin(), perm.end()));
    for (size_t k = 0; k < list_a.size(); ++k) {
      const auto& ca = m_.a.chains[list_a[k]];
      const auto& cb = m_.b.chains[best_p[k]];
      bool reversed = !(map_[ca.from] == cb.from && map_[ca.to] == cb.to);
      if (ca.from == ca.to) {  // a loop: its direction is chosen by geometry
        const Eigen::Vector3d p = chain_point(na_, ca, 0.25, false);
        reversed = (chain_point(nb_, cb, 0.25, true) - p).norm() < (chain_point(nb_, cb, 0.25, false) - p).norm();
      }
      chain_map[list_a[k]] = {best_p[k], reversed};
    }
  }
  return chain_map;
}

// The mean squared distance of the chain samples A (in a) to B (in b) after the rotation that best
// aligns the cores: each junction and its chains' first 6 % of the skeleton's length.
double Matcher::core_pose(const std::vector<Eigen::Vector3d>& A, const std::vector<Eigen::Vector3d>& B,
                          const std::vector<std::pair<int, bool>>& chain_map) const {
  std::vector<Eigen::Vector3d> ca, cb;
  for (size_t c = 0; c < chain_map.size(); ++c) {
    const auto& x = m_.a.chains[c];
    const auto& y = m_.b.chains[chain_map[c].first];
    const double f = std::min(0.5, 0.06 * total_a_ / std::max(x.length, 1e-300));
    for (double t : {0.0, 0.5, 1.0}) {
      if (m_.a.key_degree[x.from] >= 3) ca.push_back(chain_point(na_, x, t * f, false)), cb.push_back(chain_point(nb_, y, t * f, chain_map[c].second));
      if (m_.a.key_degree[x.to] >= 3) ca.push_back(chain_point(na_, x, 1 - t * f, false)), cb.push_back(chain_point(nb_, y, 1 - t * f, chain_map[c].second));
    }
  }
  if (ca.size() < 3) return INFINITY;
  Eigen::Vector3d ma = Eigen::Vector3d::Zero(), mb = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < ca.size(); ++i) ma += ca[i], mb += cb[i];
  ma /= double(ca.size()), mb /= double(cb.size());
  for (size_t i = 0; i < ca.size(); ++i) ca[i] -= ma, cb[i] -= mb;
  Eigen::Matrix3d R;
  kabsch(ca, cb, R);
  double e = 0;
  for (size_t i = 0; i < A.size(); ++i) e += (R * (A[i] - ma) + mb - B[i]).squaredNorm();
  return e / double(std::max<size_t>(1, A.size()));
}

// Scores a complete key assignment (chains paired, aligned by the best rotation) and keeps it.
void Matcher::evaluate() {
  ++m_.candidates;
  const std::vector<std::pair<int, bool>> chain_map = pair_chains();
  std::vector<Eigen::Vector3d> A, B;
  double length_term = 0;
  for (size_t c = 0; c < chain_map.size(); ++c) {
    const auto& ca = m_.a.chains[c];
    const auto& cb = m_.b.chains[chain_map[c].first];
    for (double f : {0.0, 0.25, 0.5, 0.75, 1.0}) {
      A.push_back(chain_point(na_, ca, f, false));
      B.push_back(chain_point(nb_, cb, f, chain_map[c].second));
    }
    const double d = ca.length / total_a_ - cb.length / total_b_;
    length_term += d * d;
  }
  Eigen::Matrix3d R;
  const double shape = kabsch(A, B, R) + length_term;
  double pose = 0;
  for (size_t i = 0; i < A.size(); ++i) pose += (A[i] - B[i]).squaredNorm();
  pose /= double(std::max<size_t>(1, A.size()));
  kept_.push_back({map_, chain_map, R, length_term, shape, pose, core_pose(A, B, chain_map)});
  if (kept_.size() > 20000) {  // a very symmetric graph: the lowest on shape + pose stay
    std::nth_element(kept_.begin(), kept_.begin() + 10000, kept_.end(),
                     [](const Candidate& x, const Candidate& y) { return x.shape + x.pose < y.shape + y.pose; });
    kept_.resize(10000);
  }
}

// The candidate of the lowest score (see the class comment) into the match.
void Matcher::choose() {
  if (kept_.empty()) return;
  const bool same_orientation = same_orientation_;
  auto total = [&](const Candidate& c) { return c.shape + kLengths * c.lengths + (same_orientation ? c.pose : c.core_pose); };
  const Candidate* best = nullptr;
  for (const auto& c : kept_) {
    const bool better = !best || total(c) < total(*best) - 1e-12 || (total(c) <= total(*best) + 1e-12 && c.shape < best->shape);
    if (better) best = &c;
  }
  for (const auto& c : kept_)
    if (&c != best) second_ = std::min(second_, total(c));
  best_total_ = total(*best);
  m_.key_a_to_b = best->map;
  m_.chain_a_to_b = best->chains;
  m_.rotation = best->rotation;
  m_.cost = best->shape;
}

double Matcher::disagreement(const Candidate& c) const { return chain_disagreement(m_.a, m_.b, c.chains, 0.05); }

std::vector<SkeletonMatch> Matcher::alternatives(size_t count) const {
  std::vector<const Candidate*> order;
  for (const auto& c : kept_) order.push_back(&c);
  auto own = [](const Candidate* c) { return c->shape + kLengths * c->lengths + c->pose; };
  auto core = [](const Candidate* c) { return c->shape + kLengths * c->lengths + c->core_pose; };
  std::vector<SkeletonMatch> out;
  auto add = [&](const Candidate* c) {
    for (const auto& m : out)
      if (m.key_a_to_b == c->map) return;
    SkeletonMatch m = m_;
    m.key_a_to_b = c->map, m.chain_a_to_b = c->chains, m.rotation = c->rotation, m.cost = c->shape;
    out.push_back(std::move(m));
  };
  // Candidates whose chains disagree in length (a head for an arm) take no place while others
  // agree: on TOSCA man -> gorilla they filled three of the four places and left the feet swapped.
  std::vector<const Candidate*> plausible;
  for (const Candidate* c : order)
    if (disagreement(*c) <= kPlausible) plausible.push_back(c);
  if (!plausible.empty()) order = plausible;
  if (order.empty()) return out;
  add(*std::min_element(order.begin(), order.end(), [&](auto x, auto y) { return own(x) < own(y); }));
  std::stable_sort(order.begin(), order.end(), [&](auto x, auto y) { return core(x) < core(y); });
  for (const Candidate* c : order) {
    if (out.size() >= count) break;
    add(c);
  }
  return out;
}

// Both skeletons reduced to keys and chains, or InputError naming how their branchings differ.
SkeletonMatch reduced_pair(const Skeleton& sa, const Skeleton& sb) {
  const std::string diff = branching_difference(sa, sb);
  if (!diff.empty()) throw InputError("the skeletons' branchings differ (source vs target): " + diff);
  SkeletonMatch m;
  m.a = reduce_skeleton(sa);
  m.b = reduce_skeleton(sb);
  if (m.a.keys.size() != m.b.keys.size() || m.a.chains.size() != m.b.chains.size())
    throw InputError("the skeletons' branchings differ: " + std::to_string(m.a.keys.size()) + " vs " + std::to_string(m.b.keys.size()) +
                     " junctions and ends, " + std::to_string(m.a.chains.size()) + " vs " + std::to_string(m.b.chains.size()) +
                     " chains");
  return m;
}

// The refusal when the search found no isomorphism (none at all, or none keeping the `fixed` pairs).
[[noreturn]] void throw_unmatched(const std::vector<std::pair<int, int>>& fixed) {
  throw InputError(fixed.empty() ? "the skeletons have the same junction degrees but are connected differently"
                                 : "no match of the skeletons satisfies the --match pairs");
}

}  // namespace

std::vector<SkeletonMatch> match_candidates(const Skeleton& sa, const Skeleton& sb, const std::vector<std::pair<int, int>>& fixed,
                                            int count) {
  SkeletonMatch m = reduced_pair(sa, sb);
  Matcher matcher(m, sa, sb, forced_keys(m, fixed), true);
  matcher.assign(0);
  std::vector<SkeletonMatch> out = matcher.alternatives(size_t(std::max(count, 1)));
  if (out.empty()) throw_unmatched(fixed);
  for (auto& x : out) x.candidates = m.candidates;
  return out;
}

double length_disagreement(const SkeletonMatch& m, double min_share) {
  return chain_disagreement(m.a, m.b, m.chain_a_to_b, min_share);
}

SkeletonMatch match_skeletons(const Skeleton& sa, const Skeleton& sb, const std::vector<std::pair<int, int>>& fixed,
                              bool same_orientation) {
  SkeletonMatch m = reduced_pair(sa, sb);
  Matcher matcher(m, sa, sb, forced_keys(m, fixed), same_orientation);
  matcher.assign(0);
  matcher.choose();
  if (m.key_a_to_b.empty()) throw_unmatched(fixed);
  const double second = matcher.second(), best_total = matcher.best_total();
  m.confidence = std::isfinite(second) && second > 0 ? std::clamp(1.0 - best_total / second, 0.0, 1.0) : 1.0;
  return m;
}

}  // namespace sdm
