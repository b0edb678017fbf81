#include "libstm/correspondence/register_bodies.h"

#include "libstm/geometry/triangle_bvh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/registration/articulated_registration.h"
#include "libstm/registration/fit_skeleton.h"
#include "libstm/correspondence/end_bends.h"

#include <algorithm>
#include <sstream>
#include <cmath>
#include <map>
#include <string>

namespace sdm {

namespace {

// Two candidates closer than both of these (relative twist, relative RMS) cannot be told apart: a
// mirror and the right match of 007 -> 085 with both models moved by 1e-7 tied at 0.25-0.4 % of twist
// and 1.3-1.6 % of fit, once each way; right choices have been 1.8 % or more apart in twist or 2.9 %
// in fit from every candidate that maps the ends otherwise.
constexpr double kTieTwist = 0.01, kTieFit = 0.02;
// ... nor two whose scores (candidate_score) lie within this fraction of each other: right choices
// have been 3.7 % or more below every candidate that maps the ends otherwise, and the two wrong ones
// closer than that 0.9 % (FAUST 007 onto 024 moved by 1e-7 of the diagonal, a mirror, under powers
// 3/4 and 1/2) and 1.8 % (FAUST 024 onto the TOSCA man so moved, the hands crossed).
constexpr double kScoreTie = 0.02;
// How much less alike a candidate's ends may bend than the most alike candidate's
// (end_bend_agreement) and still be chosen: the right match and its mirror differ by 0.38 or more
// on the 20 ordered pairs of the five shared bodies (0.4-3.6; a foot's bend counts up to 1).
constexpr double kFrontBack = 0.4;
// ... unless they bend alike by this much themselves: a match that crosses only the hands turns the
// core partly, and may bend the feet more alike than the right match does (the TOSCA man onto FAUST
// 024 moved by 1e-7: 1.19 crossed against 0.71 right). Mirrors measured up to 0.3.
constexpr double kBendsAlike = 0.5;
// Candidate matches examined for the distortion of their ends' distances, per one registered.
constexpr int kCandidateFactor = 4;

// A candidate's score: its twist (ArticulatedFit::twist, degrees) times the RMS of its short
// registration to the power 3/4 times the square root of its attachment misfit (attachment_misfit;
// 0, under three places to compare, counts as 0.1 % of the diagonal). Each measure sees one kind of
// wrong match: a mirror (left and right swapped with front and back) fits about as closely but
// turns parts 10-35 % more against their neighbours; a pair of limbs crossed and the others kept
// turns parts as little or less (FAUST 024 -> TOSCA man from the OFF coordinates: 10 % less) but
// lays the places where the limbs meet the torso 1.4-1.9 times as far apart, while between a mirror
// and the right match the attachments differ by chance (as much as 1.42 times), so they weigh least.
// Measured (DECISIONS 5, "One score for the candidates") on the 20 ordered pairs of the five shared bodies written four
// ways (the source as float PLY and as the OFF's own digits; the source, or the target, moved by
// 1e-7 of the diagonal) with every candidate forced in turn and checked against landmarks: the least
// score is right in 58 of the 63 runs where a candidate is right, each at least 3.7 % below every
// candidate that maps the ends otherwise (the rule before, below: 54 right; powers 1 and 1/2: 58, margins
// down to 0.8 %; 1 and 1: 57). Of the five left, one is within kScoreTie (refused) and four are
// mirrors that twist and fit favour by 13-40 %.
double candidate_score(const BodyRegistration& r, size_t i) {
  return r.candidate_twist[i] * std::pow(r.candidate_rms[i], 0.75) * std::sqrt(std::max(r.candidate_attachment[i], 1e-3));
}

// The candidate register_bodies keeps: the least score. Before the score, the least twist, unless a
// closer fit within 7 % of its twist and 1.3 times its attachment misfit: it crossed the hands of
// FAUST 024 and the TOSCA man (either way) read from their OFF files, the least twist there being a
// crossing whose attachments lay 1.9 times as far apart.
// Only candidates whose ends bend about as alike as the most alike (within kFrontBack) compete, and
// only they can tie with the chosen one (ambiguity): a mirrored match bends them the other way
// (0.4-3.6 lower than the right match on the 20 ordered pairs of the five shared bodies), where
// twist, fit and attachments favoured four mirrors by 13-40 %.
bool bends_the_other_way(const BodyRegistration& r, size_t i) {
  if (i >= r.candidate_bend.size()) return false;
  return r.candidate_bend[i] < kBendsAlike &&
         r.candidate_bend[i] < *std::max_element(r.candidate_bend.begin(), r.candidate_bend.end()) - kFrontBack;
}

int choose_candidate(const BodyRegistration& r) {
  int best = -1;
  double least = INFINITY;
  for (size_t i = 0; i < r.candidate_twist.size(); ++i) {
    if (bends_the_other_way(r, i)) continue;
    const double score = candidate_score(r, i);
    if (std::isfinite(score) && score < least) least = score, best = int(i);
  }
  return std::max(best, 0);
}

// Source end -> target end (given numbering) of a candidate match.
std::vector<std::pair<int, int>> end_pairs(const SharedSkeletons& c) {
  const SkeletonMatch m = match_in_given_numbering(c);
  std::vector<std::pair<int, int>> out;
  for (size_t k = 0; k < m.a.keys.size(); ++k)
    if (m.a.key_degree[k] == 1) out.push_back({m.a.keys[k], m.b.keys[size_t(m.key_a_to_b[k])]});
  std::sort(out.begin(), out.end());
  return out;
}

// BodyRegistration::ambiguity for the chosen candidate: empty, or which other one ties with it.
std::string ambiguity(const std::vector<SharedSkeletons>& cands, const BodyRegistration& r) {
  const size_t c = size_t(r.chosen);
  const std::vector<std::pair<int, int>> chosen_ends = end_pairs(cands[c]);
  for (size_t i = 0; i < cands.size(); ++i) {
    if (i == c || bends_the_other_way(r, i)) continue;
    const bool tie = (std::abs(r.candidate_twist[i] - r.candidate_twist[c]) <= kTieTwist * r.candidate_twist[c] &&
                      std::abs(r.candidate_rms[i] - r.candidate_rms[c]) <= kTieFit * r.candidate_rms[c]) ||
                     candidate_score(r, i) <= (1 + kScoreTie) * candidate_score(r, c);
    if (!tie || end_pairs(cands[i]) == chosen_ends) continue;
    std::ostringstream s;
    s.precision(3);
    s << "candidate matches " << c + 1 << " and " << i + 1 << " send the source's ends to different target ends, yet score within "
      << 100 * (candidate_score(r, i) / candidate_score(r, c) - 1) << " % of each other (fit within "
      << 100 * std::abs(r.candidate_rms[i] / r.candidate_rms[c] - 1) << " %, parts turned within "
      << 100 * std::abs(r.candidate_twist[i] / r.candidate_twist[c] - 1) << " %)";
    return s.str();
  }
  return "";
}

// Two full fits whose final scores (final_score) lie within this fraction of each other cannot be
// told apart: left and right (or front and back) are then a guess (BodyRegistration::ambiguity).
constexpr double kFinalTie = 0.03;

// The best-scoring candidate that sends the source's ends to other target ends than the chosen one
// (a mirror, or front and back the other way), or -1.
int symmetric_rival(const std::vector<SharedSkeletons>& cands, const BodyRegistration& r) {
  const std::vector<std::pair<int, int>> chosen_ends = end_pairs(cands[size_t(r.chosen)]);
  int best = -1;
  for (size_t i = 0; i < cands.size(); ++i) {
    if (int(i) == r.chosen || !std::isfinite(candidate_score(r, i)) || end_pairs(cands[i]) == chosen_ends) continue;
    if (best < 0 || candidate_score(r, i) < candidate_score(r, size_t(best))) best = int(i);
  }
  return best;
}

// A full fit's score: the twist of its fitted nodes (mean angle between the rotations of
// neighbouring nodes, degrees) times its RMS to the power 3/4, as candidate_score weighs the short
// registrations' (a match with ends swapped fits only by turning parts against their neighbours).
double final_score(const Skeleton& s, const SkeletonFit& fit) {
  if (s.edges.empty() || fit.node_rotation.size() != s.nodes.size()) return NAN;
  double turn = 0;
  for (const auto& e : s.edges) {
    const Eigen::Matrix3d D = fit.node_rotation[size_t(e[0])].transpose() * fit.node_rotation[size_t(e[1])];
    turn += std::acos(std::clamp((D.trace() - 1) / 2, -1.0, 1.0)) * 180 / M_PI;
  }
  return turn / double(s.edges.size()) * std::pow(fit.rms, 0.75);
}

// The chosen match's non-rigid fit: its nodes start the fit of the source's skeleton onto the
// target (fit_skeleton from the guesses).
SkeletonFit fit_match(const Mesh& source, const Mesh& target, const SharedSkeletons& sh) {
  std::vector<double> owned(sh.a.nodes.size(), 0.0);
  for (int n : sh.a.vertex_node) owned[size_t(n)] += 1;
  const Similarity start = fit_similarity(sh.a.nodes, sh.b.nodes, owned);
  FitSkeletonOptions fo;
  fo.stride = 2;  // FAUST: the same correspondence (2.04-2.66 % against 2.05-2.68 %), 0.7 s less
  return fit_skeleton(source, sh.a, target, start, sh.b.nodes, fo);
}

// Per branch of the shared match (chain of its reduced source skeleton), how far the placed source's
// vertices on it lie from the target: RMS and 99th percentile, fractions of the target's diagonal.
std::vector<BranchFit> branch_fits(const Mesh& source, const std::vector<Eigen::Vector3d>& placed, const Mesh& target,
                                   const SharedSkeletons& sh) {
  const SkeletonMatch m = match_in_given_numbering(sh);
  std::vector<int> node_chain(sh.a.nodes.size(), -1);
  for (size_t c = 0; c < sh.chain_edges.size(); ++c)
    for (int e : sh.chain_edges[c])
      for (int x : sh.a.edges[e])
        if (node_chain[x] < 0) node_chain[x] = int(c);
  const TriangleBvh bvh(vertex_matrix(target), face_matrix(target));
  const std::vector<double> area = vertex_areas(source);
  std::vector<std::vector<double>> d(sh.chain_edges.size()), w(sh.chain_edges.size());
  for (auto v : source.vertices()) {
    const int c = node_chain[sh.a.vertex_node[v.idx()]];
    if (c < 0) continue;
    d[c].push_back(bvh.closest_point(placed[v.idx()]).distance), w[c].push_back(area[v.idx()]);
  }
  const double diag = std::max(bounding_box_diagonal(target), 1e-300);
  std::vector<BranchFit> out;
  for (size_t c = 0; c < d.size(); ++c) {
    BranchFit b;
    b.source_from = m.a.keys[m.a.chains[c].from], b.source_to = m.a.keys[m.a.chains[c].to];
    double sum = 0, W = 0;
    for (size_t i = 0; i < d[c].size(); ++i) sum += w[c][i] * d[c][i] * d[c][i], W += w[c][i];
    b.rms = W > 0 ? std::sqrt(sum / W) / diag : 0;
    b.p99 = weighted_quantile(d[c], w[c], 0.99) / diag;
    b.vertices = int(d[c].size());
    out.push_back(b);
  }
  return out;
}

// Per end node of `s` (in node order), the vertex of `mesh` it owns farthest from its neighbour
// (-1 when it owns none).
std::vector<int> end_tips(const Mesh& mesh, const Skeleton& s) {
  const auto adj = s.adjacency();
  std::vector<int> tip(s.nodes.size(), -1), out;
  std::vector<double> far(s.nodes.size(), -1);
  for (auto v : mesh.vertices()) {
    const int n = s.vertex_node[v.idx()];
    if (adj[n].size() != 1) continue;
    const double d = (point(mesh, v) - s.nodes[adj[n][0]]).norm();
    if (d > far[n]) far[n] = d, tip[n] = v.idx();
  }
  for (size_t n = 0; n < adj.size(); ++n)
    if (adj[n].size() == 1) out.push_back(tip[n]);
  return out;
}

// Distances along a mesh's surface from given vertices, computed once each.
class PathCache {
 public:
  explicit PathCache(const Mesh& mesh) : mesh_(mesh) {}
  const std::vector<double>& from(int v) {
    auto it = cache_.find(v);
    if (it == cache_.end()) it = cache_.emplace(v, edge_path_distances(mesh_, v)).first;
    return it->second;
  }

 private:
  const Mesh& mesh_;
  std::map<int, std::vector<double>> cache_;
};

// How much a map changes the distances along the surfaces between corresponding points (tips_a[i]
// of the source <-> tips_b[i] of the target; -1: left out), each over the square root of its
// surface's area (sa, ta): sum |difference| / sum source distance. Bending keeps such distances and
// other bodies of one kind change them by their proportions; a map that puts a head on a foot, or
// swaps hands and feet (a gorilla's arms are longer than its legs, a man's shorter), changes the
// distances from the head most. Intrinsic, so blind to left and right.
double path_distortion(const std::vector<int>& tips_a, const std::vector<int>& tips_b, PathCache& ps, PathCache& pt, double sa, double ta) {
  double diff = 0, sum = 0;
  for (size_t i = 0; i < tips_a.size() && i < tips_b.size(); ++i) {
    if (tips_a[i] < 0 || tips_b[i] < 0) continue;
    for (size_t j = i + 1; j < tips_a.size() && j < tips_b.size(); ++j) {
      if (tips_a[j] < 0 || tips_b[j] < 0) continue;
      const double x = ps.from(tips_a[i])[tips_a[j]] / std::sqrt(sa), y = pt.from(tips_b[i])[tips_b[j]] / std::sqrt(ta);
      if (std::isfinite(x) && std::isfinite(y)) diff += std::abs(x - y), sum += x;
    }
  }
  return sum > 0 ? diff / sum : 0;
}

// Per source vertex in `tips`, the target vertex nearest its placed position (the corner of the
// closest target face nearest the closest point).
std::vector<int> images_of(const std::vector<int>& tips, const std::vector<Eigen::Vector3d>& placed, const Mesh& target, const TriangleBvh& bvh) {
  std::vector<int> image;
  for (int t : tips) {
    const auto c = bvh.closest_point(placed[t]);
    int best = -1;
    for (auto v : target.fv_range(target.face_handle(c.face)))
      if (best < 0 || (point(target, v) - c.point).norm() < (point(target, target.vertex_handle(best)) - c.point).norm()) best = v.idx();
    image.push_back(best);
  }
  return image;
}

// Where each end branch of a shared match meets the core (the junctions and the chains between
// them: a torso) on a mesh: the mean of the vertices on either side of the mesh edges between a
// vertex of the core and one of the branch (NaN when they do not touch). Pose hardly moves it (a
// shoulder, a hip, the neck), and it lies on the branch's own side of the core.
std::vector<Eigen::Vector3d> attachments(const Mesh& mesh, const std::vector<int>& vertex_node, const std::vector<int>& chain_of,
                                         size_t chains) {
  std::vector<Eigen::Vector3d> sum(chains, Eigen::Vector3d::Zero());
  std::vector<double> count(chains, 0);
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    const auto u = mesh.from_vertex_handle(h), v = mesh.to_vertex_handle(h);
    const int a = chain_of[vertex_node[u.idx()]], b = chain_of[vertex_node[v.idx()]];
    const int branch = a == -2 && b >= 0 ? b : b == -2 && a >= 0 ? a : -1;
    if (branch >= 0) sum[branch] += point(mesh, u) + point(mesh, v), count[branch] += 2;
  }
  std::vector<Eigen::Vector3d> out;
  for (size_t c = 0; c < chains; ++c) out.push_back(count[c] > 0 ? Eigen::Vector3d(sum[c] / count[c]) : Eigen::Vector3d::Constant(NAN));
  return out;
}

// Per shared node of a match, its end chain (chain of match.a), or -2 for the core.
std::vector<int> end_chain_of(const SharedSkeletons& sh) {
  const ReducedSkeleton& red = sh.match.a;
  std::vector<int> chain_of(sh.a.nodes.size(), -1);
  for (size_t k = 0; k < red.keys.size(); ++k)
    if (red.key_degree[k] >= 3) chain_of[k] = -2;
  for (size_t c = 0; c < red.chains.size(); ++c) {
    const bool core = red.key_degree[red.chains[c].from] >= 3 && red.key_degree[red.chains[c].to] >= 3;
    for (int e : sh.chain_edges[c])
      for (int n : sh.a.edges[e])
        if (chain_of[n] == -1) chain_of[n] = core ? -2 : int(c);
  }
  return chain_of;
}

// Where the end branches meet the core on each model (attachments), by end node of the common
// branching (match.a.keys on the source, match.b.keys on the target), measured on one candidate.
// A candidate of exchanged_branches takes those of the first candidate without exchanged branches,
// so that it differs only in which ends it pairs: its own resampling runs its first edges across
// the torso and hands chest vertices to an arm (measured on it, the right match's attachments lay
// 4.3 % apart and a mirror's 2.5 %: jittered FAUST 007 -> 024).
struct EndAttachments {
  std::map<int, Eigen::Vector3d> a, b;
};
EndAttachments end_attachments(const Mesh& source, const Mesh& target, const SharedSkeletons& sh) {
  const ReducedSkeleton& red = sh.match.a;
  const std::vector<int> chain_of = end_chain_of(sh);
  const auto pa = attachments(source, sh.a.vertex_node, chain_of, red.chains.size());
  const auto pb = attachments(target, sh.b.vertex_node, chain_of, red.chains.size());
  EndAttachments out;
  for (size_t c = 0; c < red.chains.size(); ++c) {
    const int from = red.chains[c].from, to = red.chains[c].to;
    const int end = red.key_degree[from] == 1 ? from : red.key_degree[to] == 1 ? to : -1;
    if (end < 0 || red.key_degree[from] + red.key_degree[to] == 2) continue;  // core chain, or a lone path
    out.a[red.keys[end]] = pa[c];
    out.b[sh.match.b.keys[size_t(sh.match.key_a_to_b[end])]] = pb[c];
  }
  return out;
}

// How far a match's end branches meet the core at other places on the two models: the RMS distance,
// over the target's diagonal, between the target's attachments (and core nodes) and the source's
// under the similarity that best lays the latter onto the former. A match that crosses one pair of
// limbs and keeps the others (hands swapped, feet not) cannot lay them together; one that swaps
// every pair (a mirror) can, as the attachments lie near a plane, so this does not tell mirrors
// apart. 0 with fewer than three points.
double attachment_misfit(const Mesh& target, const SharedSkeletons& sh, const EndAttachments& at) {
  const ReducedSkeleton& red = sh.match.a;
  std::vector<Eigen::Vector3d> x, y;
  for (size_t k = 0; k < red.keys.size(); ++k) {
    if (red.key_degree[k] != 1) continue;
    const auto p = at.a.find(red.keys[k]), q = at.b.find(sh.match.b.keys[size_t(sh.match.key_a_to_b[k])]);
    if (p != at.a.end() && q != at.b.end() && p->second.allFinite() && q->second.allFinite()) x.push_back(p->second), y.push_back(q->second);
  }
  const std::vector<int> chain_of = end_chain_of(sh);
  for (size_t n = 0; n < chain_of.size(); ++n)
    if (chain_of[n] == -2) x.push_back(sh.a.nodes[n]), y.push_back(sh.b.nodes[n]);
  if (x.size() < 3) return 0;
  const Similarity T = fit_similarity(x, y, std::vector<double>(x.size(), 1.0));
  double e = 0;
  for (size_t i = 0; i < x.size(); ++i) e += (T(x[i]) - y[i]).squaredNorm();
  return std::sqrt(e / double(x.size())) / std::max(bounding_box_diagonal(target), 1e-300);
}

// The smaller core share (core_share) of the two skeletons of a match. Under kCoreShare the
// attachments of one model all surround one point and cannot be compared with the other's: TOSCA's
// gorilla as read from its OFF file gets its legs at one junction and its head and arms at another
// 0.5 % of the length away, and every candidate onto the man measured 9.2-10.3 % (FAUST and the man:
// about 10 %).
double smaller_core_share(const SkeletonMatch& m) { return std::min(core_share(m.a), core_share(m.b)); }

}  // namespace

BodyRegistration register_bodies(const Mesh& source, const Skeleton& skeleton_a, const Mesh& target, const Skeleton& skeleton_b,
                                 const std::vector<std::pair<int, int>>& fixed, const BodyOptions& opt) {
  BodyRegistration r;
  report_progress(opt.progress, "matching the skeletons' branches (candidates for the registration)");
  std::vector<SharedSkeletons> cands = share_skeletons_candidates(source, skeleton_a, target, skeleton_b, fixed, opt.split_ratio,
                                                                  std::max(opt.candidates, 1) * kCandidateFactor);
  // Each candidate's short articulated registration (every 4th vertex paired): the match whose
  // parts turn least against their neighbours (ArticulatedFit::twist: a mirrored match fits the
  // surfaces about as closely by turning parts around), with the closest fit and the places where
  // the limbs meet the torso least apart, wins (choose_candidate).
  ArticulatedOptions quick;
  quick.iterations = 12, quick.refine = false, quick.stride = 4;
  double source_area = 0, target_area = 0;
  for (double a : vertex_areas(source)) source_area += a;
  for (double a : vertex_areas(target)) target_area += a;
  // The candidates whose matched ends (each end's tip on either model) keep the distances along
  // the surfaces best go on.
  PathCache source_cache(source), target_cache(target);
  std::vector<std::pair<double, size_t>> order;
  for (size_t i = 0; i < cands.size(); ++i)
    order.push_back({path_distortion(end_tips(source, cands[i].a), end_tips(target, cands[i].b), source_cache, target_cache, source_area,
                                     target_area),
                     i});
  std::stable_sort(order.begin(), order.end());
  report_progress(opt.progress, std::to_string(cands.size()) + " candidate matches: the distances between their matched ends change by " +
                                    std::to_string(100 * order.front().first) + " to " + std::to_string(100 * order.back().first) + " %");
  size_t plain = 0;  // the first candidate without exchanged branches measures the attachments
  while (plain + 1 < cands.size() && cands[plain].exchanged) ++plain;
  const EndAttachments attached = end_attachments(source, target, cands[plain]);
  std::vector<SharedSkeletons> kept;
  for (size_t i = 0; i < order.size() && int(kept.size()) < std::max(opt.candidates, 1); ++i) kept.push_back(std::move(cands[order[i].second]));
  cands = std::move(kept);
  // After each registration: the source's extremities against their images on the target.
  std::vector<int> tips;
  for (int t : end_tips(source, cands[0].a))
    if (t >= 0) tips.push_back(t);
  const TriangleBvh bvh(vertex_matrix(target), face_matrix(target));
  auto extremity_distortion = [&](const std::vector<Eigen::Vector3d>& placed) {
    return path_distortion(tips, images_of(tips, placed, target, bvh), source_cache, target_cache, source_area, target_area);
  };
  for (size_t i = 0; i < cands.size(); ++i) {
    const ArticulatedFit f = articulated_registration(source, cands[i].a, target, cands[i].b.nodes, quick);
    r.candidate_rms.push_back(f.posed_rms), r.candidate_twist.push_back(f.twist);
    r.candidate_distortion.push_back(extremity_distortion(f.posed));
    r.candidate_attachment.push_back(attachment_misfit(target, cands[i], cands[i].exchanged ? attached : end_attachments(source, target, cands[i])));
    r.candidate_bend.push_back(end_bend_agreement(cands[i].a, cands[i].b));
    report_progress(opt.progress, "candidate match " + std::to_string(i + 1) + " of " + std::to_string(cands.size()) + ": RMS " +
                                      std::to_string(100 * f.posed_rms) + " % of the diagonal, parts turned " + std::to_string(f.twist) +
                                      " degrees against their neighbours, extremities' distances changed by " +
                                      std::to_string(100 * r.candidate_distortion.back()) + " %, branches attached " +
                                      std::to_string(100 * r.candidate_attachment.back()) + " % apart, ends bend alike " +
                                      std::to_string(r.candidate_bend.back()));
  }
  r.chosen = choose_candidate(r);
  r.ambiguity = ambiguity(cands, r);
  // The chosen match's nodes start the non-rigid fit (fit_skeleton from the guesses). The full
  // articulated registration before it (30 steps, then fit_skeleton from its pose and from the
  // guesses, the closer kept) gave the same correspondence on FAUST (2.05-2.68 % against 2.05-2.68 %,
  // 024 -> 007 2.34 % against 2.45 %) in twice the time.
  report_progress(opt.progress, "bending the source onto the target along its skeleton");
  SkeletonFit fit = fit_match(source, target, cands[size_t(r.chosen)]);
  r.rival = opt.fit_rival ? symmetric_rival(cands, r) : -1;
  if (r.rival >= 0) {
    // The symmetric rival through the whole fit as well: the short registrations' score can favour a
    // mirror (DECISIONS 5, "Symmetric candidates"); the lower final score is kept, and a tie reported.
    report_progress(opt.progress, "bending the source along the symmetric rival, candidate match " + std::to_string(r.rival + 1));
    SkeletonFit other = fit_match(source, target, cands[size_t(r.rival)]);
    r.final_score = final_score(cands[size_t(r.chosen)].a, fit), r.rival_score = final_score(cands[size_t(r.rival)].a, other);
    report_progress(opt.progress, "final scores: chosen " + std::to_string(r.final_score) + " (RMS " + std::to_string(100 * fit.rms) +
                                      " %), rival " + std::to_string(r.rival_score) + " (RMS " + std::to_string(100 * other.rms) + " %)");
    if (r.rival_score < r.final_score) {
      std::swap(fit, other), std::swap(r.chosen, r.rival), std::swap(r.final_score, r.rival_score);
      r.switched = true;
      r.ambiguity = ambiguity(cands, r);
    }
    if (r.ambiguity.empty() && r.rival_score <= (1 + kFinalTie) * r.final_score) {
      std::ostringstream s;
      s.precision(3);
      s << "candidate matches " << r.chosen + 1 << " and " << r.rival + 1 << " send the source's ends to different target ends, yet "
        << "their full fits score within " << 100 * (r.rival_score / r.final_score - 1) << " % of each other";
      r.ambiguity = s.str();
    }
  }
  r.attachment = smaller_core_share(cands[size_t(r.chosen)].match) >= kCoreShare ? r.candidate_attachment[size_t(r.chosen)] : 0;
  r.skeletons = std::move(cands[size_t(r.chosen)]);
  r.rms = fit.rms, r.p99 = fit.p99;
  r.branch_fit = branch_fits(source, fit.bent, target, r.skeletons);
  r.distortion = extremity_distortion(fit.bent);
  r.placed = std::move(fit.bent);
  return r;
}


}  // namespace sdm
