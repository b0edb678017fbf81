#include "libstm/transfer/register_bodies.h"

#include "libstm/geometry/triangle_bvh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/registration/articulated_registration.h"
#include "libstm/registration/fit_skeleton.h"

#include <cmath>
#include <string>

namespace sdm {

namespace {

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

}  // namespace

BodyRegistration register_bodies(const Mesh& source, const Skeleton& skeleton_a, const Mesh& target, const Skeleton& skeleton_b,
                                 const std::vector<std::pair<int, int>>& fixed, const BodyOptions& opt) {
  BodyRegistration r;
  report_progress(opt.progress, "matching the skeletons' branches (candidates for the registration)");
  std::vector<SharedSkeletons> cands = share_skeletons_candidates(source, skeleton_a, target, skeleton_b, fixed, opt.split_ratio,
                                                                  std::max(opt.candidates, 1));
  // Each candidate's short articulated registration (every 4th vertex paired): the match whose
  // parts turn least against their neighbours wins (ArticulatedFit::twist), since a swapped match
  // fits the surfaces about as closely (RMS within 0.5 % of the diagonal) by turning parts around.
  ArticulatedOptions quick;
  quick.iterations = 12, quick.refine = false, quick.stride = 4;
  size_t best = 0;
  for (size_t i = 0; i < cands.size(); ++i) {
    const ArticulatedFit f = articulated_registration(source, cands[i].a, target, cands[i].b.nodes, quick);
    r.candidate_rms.push_back(f.posed_rms), r.candidate_twist.push_back(f.twist);
    report_progress(opt.progress, "candidate match " + std::to_string(i + 1) + " of " + std::to_string(cands.size()) + ": RMS " +
                                      std::to_string(100 * f.posed_rms) + " % of the diagonal, parts turned " + std::to_string(f.twist) +
                                      " degrees against their neighbours");
    if (f.twist < r.candidate_twist[best]) best = i;
  }
  r.chosen = int(best);
  r.skeletons = std::move(cands[best]);
  // The chosen match's nodes start the non-rigid fit (fit_skeleton from the guesses). The full
  // articulated registration before it (30 steps, then fit_skeleton from its pose and from the
  // guesses, the closer kept) gave the same correspondence on FAUST (2.05-2.68 % against 2.05-2.68 %,
  // 024 -> 007 2.34 % against 2.45 %) in twice the time.
  report_progress(opt.progress, "bending the source onto the target along its skeleton");
  std::vector<double> owned(r.skeletons.a.nodes.size(), 0.0);
  for (int n : r.skeletons.a.vertex_node) owned[n] += 1;
  const Similarity start = fit_similarity(r.skeletons.a.nodes, r.skeletons.b.nodes, owned);
  FitSkeletonOptions fo;
  fo.stride = 2;  // FAUST: the same correspondence (2.04-2.66 % against 2.05-2.68 %), 0.7 s less
  SkeletonFit fit = fit_skeleton(source, r.skeletons.a, target, start, r.skeletons.b.nodes, fo);
  r.rms = fit.rms, r.p99 = fit.p99;
  r.branch_fit = branch_fits(source, fit.bent, target, r.skeletons);
  r.placed = std::move(fit.bent);
  return r;
}


}  // namespace sdm
