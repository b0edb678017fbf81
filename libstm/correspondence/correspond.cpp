#include "libstm/correspondence/correspond.h"

#include "libstm/core/errors.h"
#include "libstm/core/parallel.h"
#include "libstm/correspondence/end_distances.h"
#include "libstm/registration/carry_skeleton.h"
#include "libstm/registration/fit_skeleton.h"
#include "libstm/registration/mend_islands.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <sstream>

namespace sdm {

const char* kind_name(CorrespondenceKind kind) {
  switch (kind) {
    case CorrespondenceKind::carried: return "carried";
    case CorrespondenceKind::bent: return "bent";
    case CorrespondenceKind::registered: return "registered";
    default: return "skeleton only";
  }
}

const char* other_candidates_named(bool source, bool target) {
  return source && target ? "source and the target" : source ? "source" : "target";
}

CorrespondenceKind recognised_kind(const Registration& moved, const SkeletonFit* bent, const CorrespondOptions& opt) {
  // Every test is a comparison that a NaN fails: a measure that is not a number takes nothing.
  if (moved.rms <= opt.same_shape_rms && moved.p99 <= opt.same_shape_p99) return CorrespondenceKind::carried;
  if (!bent) return CorrespondenceKind::skeleton_only;
  // When bending explains little of the distance, the target is the source's shape and the
  // distance is the tessellations' (a coarse polyhedron and its remesh, which cuts its corners:
  // the double torus of the tests, 0.51 % moved as a whole, 0.40 % bent); moved as a whole,
  // the source lines up with it exactly, where the bent fit slides.
  if (moved.rms <= 2 * opt.same_shape_rms && moved.p99 <= opt.same_shape_p99 && moved.rms <= 1.5 * bent->rms)
    return CorrespondenceKind::carried;
  if (bent->rms <= opt.fit_rms && bent->p99 <= opt.fit_p99 && bent->end_spread >= opt.fit_spread) return CorrespondenceKind::bent;
  return CorrespondenceKind::skeleton_only;
}

namespace {

// What the stages found so far: the diagnostics, what the target was found to be, and the matched
// skeletons.
struct Work : CorrespondenceDiagnostics {
  CorrespondenceKind kind = CorrespondenceKind::skeleton_only;
  SharedSkeletons skeletons;
};

// The target's skeleton as the transfer takes it, and what comes with it.
struct TargetSkeleton {
  Skeleton skeleton;                           // skeleton_b, or the source's carried or bent onto the target
  std::vector<Eigen::Matrix3d> node_rotation;  // of skeleton_a's nodes, when bent onto the target
  std::vector<Eigen::Vector3d> placed;         // the source's vertices on the target (carried or bent)
};

// The Euler characteristic of the surface with every hole capped by a disc (V - E + F + loops): an
// open scan and the closed model it was taken from have the same one.
long euler_characteristic(const Mesh& m) {
  long loops = 0;
  std::vector<char> seen(m.n_halfedges(), 0);
  for (auto h : m.halfedges()) {
    if (!m.is_boundary(h) || seen[size_t(h.idx())]) continue;
    ++loops;
    for (auto x = h; !seen[size_t(x.idx())]; x = m.next_halfedge_handle(x)) seen[size_t(x.idx())] = 1;
  }
  return long(m.n_vertices()) - long(m.n_edges()) + long(m.n_faces()) + loops;
}

// The source registered onto the target (register_surfaces). Besides the centred start, the
// similarity of the matched skeletons, when they match: it finds a turned or moved target that
// the centred start cannot reach.
Registration register_source(const Mesh& source, const Skeleton& skeleton_a, const Mesh& target, const Skeleton& skeleton_b,
                             double split_ratio) {
  std::vector<Similarity> starts;
  try {
    const SharedSkeletons sh = share_skeletons(source, skeleton_a, target, skeleton_b, {}, split_ratio);
    starts.push_back(fit_similarity(sh.a.nodes, sh.b.nodes, std::vector<double>(sh.a.nodes.size(), 1.0)));
  } catch (const InputError&) {
  }
  return register_surfaces(source, target, starts);
}

// The source's skeleton bent onto the target (fit_skeleton) from the registration alone, and from
// the matched extracted skeleton when the branchings match (it knows where a turned limb went):
// the closer fit (by RMS).
SkeletonFit bend_source(const Mesh& source, const Skeleton& skeleton_a, const Mesh& target, const Skeleton& skeleton_b,
                        const Similarity& start) {
  std::vector<std::vector<Eigen::Vector3d>> guesses{{}};
  try {
    guesses.push_back(skeleton_onto_graph(skeleton_a, skeleton_b).nodes);
  } catch (const InputError&) {
  }
  SkeletonFit best;
  for (const auto& guess : guesses) {
    FitSkeletonOptions fo;
    fo.stride = 2;  // FAUST 007 -> 024: 3.6 s -> 2.8 s, the bent RMS 0.927 % -> 0.928 %
    SkeletonFit f = fit_skeleton(source, skeleton_a, target, start, guess, fo);
    if (f.rms < best.rms) best = std::move(f);
  }
  return best;
}

// Is the target the source's shape (carried), the source in another pose (bent), or neither
// (CorrespondOptions::carry_same_shape; recognised_kind)? Fills r.registration, r.kind, r.fit_rms
// and r.fit_p99; returns the target's skeleton (skeleton_b when neither).
TargetSkeleton recognise_target(const Mesh& source, const Skeleton& skeleton_a, const Mesh& target, const Skeleton& skeleton_b,
                                const CorrespondOptions& opt, Work& r) {
  report_progress(opt.progress, "registering the source onto the target");
  r.registration = register_source(source, skeleton_a, target, skeleton_b, opt.split_ratio);
  const Registration& g = r.registration;
  r.kind = recognised_kind(g, nullptr, opt);
  const bool carried = r.kind == CorrespondenceKind::carried;
  report_progress(opt.progress, "registered: RMS " + std::to_string(100 * g.rms) + " %, 99th percentile " + std::to_string(100 * g.p99) +
                                    " % of the diagonal, scale " + std::to_string(g.transform.scale) +
                                    (carried ? ": the same shape, the source's skeleton carried over" : ""));
  SkeletonFit best;
  if (!carried) {
    report_progress(opt.progress, "bending the source's skeleton onto the target");
    best = bend_source(source, skeleton_a, target, skeleton_b, g.transform);
    r.fit_rms = best.rms, r.fit_p99 = best.p99;
    r.kind = recognised_kind(g, &best, opt);
    report_progress(opt.progress, "bent: RMS " + std::to_string(100 * best.rms) + " %, 99th percentile " + std::to_string(100 * best.p99) +
                                      " % of the diagonal" +
                                      (r.kind == CorrespondenceKind::carried ? ": little better than moved as a whole, so the same shape: the source's skeleton carried over"
                                       : r.kind == CorrespondenceKind::bent  ? ": the source's skeleton bent onto the target"
                                                                             : ": not close enough"));
  }
  TargetSkeleton t{skeleton_b, {}, {}};
  if (r.kind == CorrespondenceKind::carried) {
    t.skeleton = carry_skeleton(source, skeleton_a, target, g.transform);
    for (auto v : source.vertices()) t.placed.push_back(g.transform(point(source, v)));
  } else if (r.kind == CorrespondenceKind::bent) {
    t.skeleton = std::move(best.skeleton), t.node_rotation = std::move(best.node_rotation), t.placed = std::move(best.bent);
  }
  return t;
}

// share_skeletons, its refusal completed (when the source was registered) with how far the target
// is from the source's shape and from a pose of it.
SharedSkeletons share_or_explain(const Mesh& source, const Skeleton& skeleton_a, const Mesh& target, const Skeleton& skeleton_b,
                                 const std::vector<std::pair<int, int>>& fixed, const CorrespondOptions& opt, const Work& r) {
  try {
    return share_skeletons(source, skeleton_a, target, skeleton_b, fixed, opt.split_ratio);
  } catch (const InputError& e) {
    if (!std::isfinite(r.registration.rms)) throw;
    auto pc = [](double x) {
      std::ostringstream o;
      o.precision(2);
      o << 100 * x << " %";
      return o.str();
    };
    throw InputError(std::string(e.what()) + "; nor is the target the source in another pose: moved as a whole, the source lies " +
                     pc(r.registration.rms) + " of the diagonal from it (RMS; the same shape is under " + pc(opt.same_shape_rms) +
                     "), bent along its skeleton " + pc(r.fit_rms) + " (under " + pc(opt.fit_rms) + " is taken)");
  }
}

// A bent source's segments (edges of the shared skeleton a) take the rotation of the fitted node
// of skeleton_a nearest to their midpoints (the first of equals).
std::vector<Eigen::Matrix3d> segment_rotations(const Skeleton& shared_a, const Skeleton& skeleton_a,
                                               const std::vector<Eigen::Matrix3d>& node_rotation) {
  std::vector<Eigen::Matrix3d> segment_rotation;
  for (const auto& e : shared_a.edges) {
    const Eigen::Vector3d mid = (shared_a.nodes[e[0]] + shared_a.nodes[e[1]]) / 2;
    size_t best = 0;
    for (size_t k = 1; k < skeleton_a.nodes.size(); ++k)
      if ((skeleton_a.nodes[k] - mid).norm() < (skeleton_a.nodes[best] - mid).norm()) best = k;
    segment_rotation.push_back(node_rotation[best]);
  }
  return segment_rotation;
}

// The target's STM coordinates through the source placed on it (carried or bent; layout_a lies
// around shared_a, the source's shared skeleton): every target point has a source point under it,
// the closest point of the placed source taken back to the source by its barycentric coordinates.
// Each target face is mapped by the source's capsules at those points, with the segment of the
// source face under its centroid (one segment for the whole face, so seams and borders between
// rectangles unwrap as in the source). The target then shows the source's texture wherever the
// surfaces correspond, however far the fitted nodes are from where the target's own shape would
// put them (capsule coordinates near a cap's pole turn fast: the fitted skeleton's own capsules
// tore the spots at the back of a turned Spot's head).
// `refine`, when given, refines the target vertices' source points (zoomout) once mended; the
// face centroids keep theirs (they choose each face's segment).
// The source points under the target's vertices and face centroids through the source placed on
// it (carried, bent or registered): the closest point of the placed source taken back to the source
// by its barycentric coordinates. Patches whose source points jump away from everything around
// them (touching parts) are looked up again near what surrounds them (mend_islands); a face
// centroid goes with its first corner in an island. `refine`, when given, refines the vertices'
// source points (zoomout) once mended; the face centroids keep theirs (the transfer chooses each
// face's segment by them).
using Refinement = std::function<std::vector<SourcePoint>(const std::vector<SourcePoint>&)>;
void source_points(const Mesh& source, const std::vector<Eigen::Vector3d>& placed, const Mesh& target, const Skeleton& shared_a,
                   Correspondence& c, const Refinement& refine) {
  std::vector<Eigen::Vector3d> points, normals(target.n_vertices(), Eigen::Vector3d::Zero());
  for (auto v : target.vertices()) points.push_back(point(target, v));
  for (auto f : target.faces()) {
    Eigen::Vector3d m = Eigen::Vector3d::Zero(), corner[3];
    int k = 0;
    for (auto v : target.fv_range(f)) m += point(target, v) / 3, corner[k++] = point(target, v);
    points.push_back(m);
    const Eigen::Vector3d n = (corner[1] - corner[0]).cross(corner[2] - corner[0]);
    for (auto v : target.fv_range(f)) normals[size_t(v.idx())] += n;
    normals.push_back(n.normalized());
  }
  for (size_t i = 0; i < target.n_vertices(); ++i) normals[i].normalize();
  std::vector<SourcePoint> at = source_points_under(source, placed, points, normals);
  const CorrespondenceIslands islands =
      find_islands(source, shared_a, target, std::vector<SourcePoint>(at.begin(), at.begin() + target.n_vertices()));
  std::vector<int> point_island = islands.island_of;
  for (auto f : target.faces()) {
    int id = -1;
    for (auto v : target.fv_range(f)) id = id >= 0 ? id : islands.island_of[size_t(v.idx())];
    point_island.push_back(id);
  }
  mend_islands(source, placed, islands, points, point_island, at);
  c.points.assign(at.begin(), at.begin() + target.n_vertices());
  c.face_points.assign(at.begin() + target.n_vertices(), at.end());
  if (refine) c.points = refine(c.points);
}

// Whether a match's branches disagree in length beyond what a registration takes
// (CorrespondOptions::registered_disagreement): refused unless forced, and the cue to try the other
// extraction candidates first.
bool lengths_disagree(const SharedSkeletons& shared, const CorrespondOptions& opt) {
  return shared.length_disagreement > opt.registered_disagreement;
}

// Whether take_registered takes `reg` without `force`: a close fit, matched branches that agree in
// length and meet the core at about the same places, and no tie between left and right.
bool registration_taken(const BodyRegistration& reg, const CorrespondOptions& opt) {
  return reg.rms <= opt.registered_rms && reg.p99 <= opt.registered_p99 && !lengths_disagree(reg.skeletons, opt) &&
         reg.attachment <= opt.registered_attachment && reg.ambiguity.empty();
}

// Takes a registration of another body (register_bodies) as the correspondence's (judged at the
// end: judge_correspondence).
void take_registered(BodyRegistration reg, const CorrespondOptions& opt, Work& r, TargetSkeleton& tb) {
  r.skeletons = std::move(reg.skeletons);
  r.fit_rms = reg.rms, r.fit_p99 = reg.p99, r.kind = CorrespondenceKind::registered;
  r.candidate_rms = std::move(reg.candidate_rms), r.branch_fit = std::move(reg.branch_fit);
  r.candidate_twist = std::move(reg.candidate_twist), r.candidate_distortion = std::move(reg.candidate_distortion);
  r.candidate_attachment = std::move(reg.candidate_attachment), r.candidate_bend = std::move(reg.candidate_bend);
  r.distortion = reg.distortion;
  r.attachment = reg.attachment;
  r.ambiguity = std::move(reg.ambiguity);
  r.rival = reg.rival, r.final_score = reg.final_score, r.rival_score = reg.rival_score, r.switched = reg.switched;
  tb.placed = std::move(reg.placed);
  const bool poor = !(r.fit_rms <= opt.registered_rms && r.fit_p99 <= opt.registered_p99);
  report_progress(opt.progress, "registered: RMS " + std::to_string(100 * r.fit_rms) + " %, 99th percentile " +
                                    std::to_string(100 * r.fit_p99) + " % of the diagonal" + (poor ? ": a poor fit" : ""));
}

// How closely a registration fits, for choosing among registrations of other skeletons of the same
// two models (smaller is better; the surfaces are the same, so the distances compare, where the
// attachments, measured between other junctions, do not: Homer onto FAUST 007 upside down 3.3 %,
// right 3.6 %, fits 0.530 and 0.507 % RMS), then how far apart it lays the attachments.
std::pair<double, double> registration_rank(const BodyRegistration& reg) { return {reg.rms, reg.attachment}; }

// The refusal's way out (CorrespondOptions::other_candidate): the pairs of given and other
// extraction candidates registered as another body (the model with fewer ends changed first), and
// of those whose branchings agree and whose matched branches agree in length
// (CorrespondOptions::registered_disagreement), or with `need_taken` that take_registered takes as
// they are (registration_taken), the one that fits closest (registration_rank). Every pair is
// tried, not the first that qualifies: Homer's medial skeleton (alecjacobson/common-3d-test-models)
// joins his right arm to the belly beside the hips; paired with FAUST 007's contraction skeleton it
// was taken (0.407 % RMS), the texture upside down, where both contraction skeletons fit 0.361 %,
// every part in place. Empty when no pair qualifies. `why` says on the progress line why the other
// candidates are extracted.
std::optional<BodyRegistration> register_other_candidates(const Mesh& source, const Skeleton& skeleton_a, const Mesh& target,
                                                          const Skeleton& skeleton_b, const CorrespondOptions& opt, bool need_taken,
                                                          const char* why, Work& r) {
  std::optional<Skeleton> other[2];
  bool asked[2] = {false, false};
  auto candidate = [&](bool is_target) -> const Skeleton* {
    if (!asked[is_target]) {
      asked[is_target] = true;
      const std::string whose = is_target ? "target" : "source";
      report_progress(opt.progress, std::string(why) + ": extracting the " + whose + "'s other candidate");
      try {  // a candidate that cannot be extracted is no candidate: the given pair's verdict stands
        other[is_target] = opt.other_candidate(is_target);
      } catch (const InputError& e) {
        report_progress(opt.progress, "the " + whose + "'s other candidate could not be extracted: " + e.what());
      }
    }
    return other[is_target] ? &*other[is_target] : nullptr;
  };
  const bool source_first = skeleton_a.end_nodes() < skeleton_b.end_nodes();
  const std::pair<bool, bool> pairs[3] = {{source_first, !source_first}, {!source_first, source_first}, {true, true}};
  BodyOptions bo;
  bo.split_ratio = opt.split_ratio, bo.candidates = opt.candidates, bo.progress = opt.progress;
  std::optional<BodyRegistration> best;
  for (const auto& [other_a, other_b] : pairs) {
    const Skeleton* a = other_a ? candidate(false) : &skeleton_a;
    const Skeleton* b = other_b ? candidate(true) : &skeleton_b;
    if (!a || !b) continue;
    try {  // register_bodies throws InputError where the branchings still differ (common_branching)
      BodyRegistration reg = register_bodies(source, *a, target, *b, {}, bo);
      if (need_taken ? !registration_taken(reg, opt) : lengths_disagree(reg.skeletons, opt)) continue;
      report_progress(opt.progress, std::string("the other candidate of the ") + other_candidates_named(other_a, other_b) +
                                        " registered: limbs meet the core " + std::to_string(100 * reg.attachment) + " % apart, RMS " +
                                        std::to_string(100 * reg.rms) + " %");
      if (best && registration_rank(reg) >= registration_rank(*best)) continue;
      best = std::move(reg);
      r.other_source_candidate = other_a, r.other_target_candidate = other_b;
    } catch (const InputError&) {
    }
  }
  return best;
}

// The target recognised (carried or bent: recognise_target) and, on a second thread beside it, the
// source registered onto it as another body (register_bodies), kept in `body` for when the target
// is neither (left empty when the branchings differ, after each model's other extraction candidate
// was tried: the skeletons' match then explains the refusal).
// Both only when the caller leaves the target's
// skeleton to the transfer (carry_same_shape) and the genera agree; the registration also needs
// register_bodies. `fixed` receives every key node as its own counterpart when carried or bent.
TargetSkeleton recognise_or_register(const Mesh& source, const Skeleton& skeleton_a, const Mesh& target, const Skeleton& skeleton_b,
                                     const CorrespondOptions& opt, Work& r, std::vector<std::pair<int, int>>& fixed,
                                     std::optional<BodyRegistration>& body) {
  TargetSkeleton tb{skeleton_b, {}, {}};
  if (!opt.carry_same_shape || euler_characteristic(source) != euler_characteristic(target)) return tb;
  CorrespondOptions o = opt;
  o.progress = serialised(opt.progress);
  std::unique_ptr<BackgroundTask> task;
  if (opt.register_bodies) {
    BodyOptions bo;
    bo.split_ratio = opt.split_ratio, bo.candidates = opt.candidates, bo.progress = o.progress;
    task = std::make_unique<BackgroundTask>([&, bo] { body = register_bodies(source, skeleton_a, target, skeleton_b, opt.fixed, bo); });
  }
  if (opt.fixed.empty()) tb = recognise_target(source, skeleton_a, target, skeleton_b, o, r);
  if (task) {
    try {
      task->wait();
    } catch (const InputError&) {
      body.reset();
    }
    // Also where the match would be refused for branches that disagree in length: a jittered FAUST
    // 024's medial skeleton lost its head, and its contraction candidate has one. And where it would
    // be refused otherwise (limbs meeting the torso at other places, a tie, a poor fit), for a pair
    // that would be taken: the TOSCA man's medial skeleton (a float PLY of it) and FAUST 024's each
    // have one small end more, at other places, so that no end is pruned and every match pairs a
    // limb with another (attachments 9.1 % apart).
    // And where it would be taken with its limbs meeting the core at places almost too far apart to
    // be (marginal_attachment), or between bodies of other proportions (marginal_distortion): Homer's
    // medial skeleton onto FAUST 007's (DECISIONS 5, "Other extraction candidates"). The given pair is kept unless another fits closer.
    const bool unmatched = !body || lengths_disagree(body->skeletons, opt);
    const bool taken = !unmatched && registration_taken(*body, opt);
    const bool marginal = taken && (body->attachment > opt.marginal_attachment || body->distortion > opt.marginal_distortion);
    if ((!taken || marginal) && r.kind == CorrespondenceKind::skeleton_only && opt.other_candidate && opt.fixed.empty()) {
      const char* why = marginal    ? "the registration is marginal (limbs meet the core far apart, or the proportions differ)"
                        : unmatched ? "the skeletons' branchings differ or disagree"
                                    : "the registration would be refused";
      std::optional<BodyRegistration> other = register_other_candidates(source, skeleton_a, target, skeleton_b, opt, !unmatched, why, r);
      if (other && (!marginal || registration_rank(*other) < registration_rank(*body))) {
        body = std::move(other);
        report_progress(opt.progress, std::string("registered with the other candidate of the ") +
                                          other_candidates_named(r.other_source_candidate, r.other_target_candidate));
      } else if (marginal) {
        r.other_source_candidate = r.other_target_candidate = false;
        report_progress(opt.progress, "the given candidates fit closest: kept");
      }
    }
  }
  // The source bent along its own skeleton is meant for the source in another pose; another body
  // can let it fit almost as closely with a limb folded into place (FAUST 024 onto 085: bent 0.377 %
  // RMS, its raised right leg crumpled at the knee and the foot's texture up the shin; registered as
  // another body 0.297 %, every part in place). The closer of the two is kept, if the registration
  // would be taken as it is.
  if (r.kind == CorrespondenceKind::bent && body && body->rms < r.fit_rms && registration_taken(*body, opt)) {
    report_progress(opt.progress, "registered as another body, the source fits closer (RMS " + std::to_string(100 * body->rms) +
                                      " % against " + std::to_string(100 * r.fit_rms) + " % bent): taken instead");
    r.kind = CorrespondenceKind::skeleton_only;
    tb = TargetSkeleton{skeleton_b, {}, {}};
  }
  if (r.kind == CorrespondenceKind::carried || r.kind == CorrespondenceKind::bent) {
    // One graph on both sides: every junction and end is its own counterpart.
    const std::vector<int> deg = skeleton_a.degrees();
    for (size_t x = 0; x < deg.size(); ++x)
      if (deg[x] != 2) fixed.emplace_back(int(x), int(x));
  }
  return tb;
}

}  // namespace

Correspondence correspond(const Mesh& source, const Skeleton& skeleton_a, const Mesh& target, const Skeleton& skeleton_b,
                          const CorrespondOptions& opt) {
  Work r;
  std::vector<std::pair<int, int>> fixed = opt.fixed;
  std::optional<BodyRegistration> body;
  TargetSkeleton tb = recognise_or_register(source, skeleton_a, target, skeleton_b, opt, r, fixed, body);
  // Neither the source's shape nor the source bent along its own skeleton: another body.
  if (r.kind == CorrespondenceKind::skeleton_only && body) {
    take_registered(std::move(*body), opt, r, tb);
  } else {
    report_progress(opt.progress, "matching the skeletons' branches");
    r.skeletons = share_or_explain(source, skeleton_a, target, tb.skeleton, fixed, opt, r);
  }
  Correspondence c;
  c.kind = r.kind;
  c.skeletons = std::move(r.skeletons);
  c.diagnostics = std::move(static_cast<CorrespondenceDiagnostics&>(r));
  judge_correspondence(c, opt);
  report_progress(opt.progress, "shared graph: " + std::to_string(c.skeletons.a.nodes.size()) + " nodes, " +
                                    std::to_string(c.skeletons.a.edges.size()) + " segments");
  if (c.kind == CorrespondenceKind::bent) c.segment_rotation = segment_rotations(c.skeletons.a, skeleton_a, tb.node_rotation);
  if (tb.placed.empty()) return c;
  // The refinement's Laplace bases depend on the meshes alone: computed beside the source points
  // under the target (DECISIONS 5, "Spectral refinement").
  const bool refined = c.diagnostics.refined = c.kind == CorrespondenceKind::registered && opt.refine;
  LaplaceBasis source_basis, target_basis;
  std::unique_ptr<BackgroundTask> bases;
  if (refined)
    bases = std::make_unique<BackgroundTask>([&] {
      run_concurrently([&] { source_basis = mesh_laplace_basis(source, opt.refinement.k_end); },
                       [&] { target_basis = mesh_laplace_basis(target, opt.refinement.k_end); });
    });
  report_progress(opt.progress, "the source points under the target");
  Refinement refine;
  if (refined)
    refine = [&](const std::vector<SourcePoint>& start) {
      bases->wait();
      report_progress(opt.progress, "refining the correspondence in the Laplace-Beltrami eigenbases");
      const ZoomOutFeatures features = opt.refinement.feature_weight > 0 ? end_distances(source, target, c.skeletons) : ZoomOutFeatures{};
      return zoomout(source, source_basis, target, target_basis, start, opt.refinement, features);
    };
  source_points(source, tb.placed, target, c.skeletons.a, c, refine);
  return c;
}

void judge_correspondence(const Correspondence& c, const CorrespondOptions& opt) {
  if (c.kind != CorrespondenceKind::registered || opt.force) return;
  const CorrespondenceDiagnostics& d = c.diagnostics;
  if (c.skeletons.length_disagreement > opt.registered_disagreement)
    throw InputError("the skeletons do not correspond branch for branch: a matched branch is " +
                     std::to_string(c.skeletons.length_disagreement) + " times longer, relative to its skeleton, than its match (up to " +
                     std::to_string(opt.registered_disagreement) + " is taken), so the texture would land on other parts. An extraction "
                     "may have missed a branch (check both with 'sdm skeleton'); pin branches with --match, or pass --force to write it anyway");
  if (d.attachment > opt.registered_attachment)
    throw InputError("the skeletons' branches are matched to other branches: where they meet the core (a torso) they lie " +
                     std::to_string(100 * d.attachment) + " % of the diagonal apart on the two models (up to " +
                     std::to_string(100 * opt.registered_attachment) + " % is taken), so the texture would land on other parts. An "
                     "extraction may have split or missed a branch (check both with 'sdm skeleton'); pin branches with --match, or pass "
                     "--force to write it anyway");
  if (!d.ambiguity.empty())
    throw InputError("left and right (or front and back) cannot be told apart: " + d.ambiguity +
                     ", so the texture may land mirrored. Pin the limbs with --match SOURCE_NODE=TARGET_NODE (ends of the "
                     "skeletons 'sdm skeleton' writes), or pass --force to take the chosen match anyway");
  if (!(d.fit_rms <= opt.registered_rms && d.fit_p99 <= opt.registered_p99))
    throw InputError("the source does not fit the target: registered along its skeleton it lies " + std::to_string(100 * d.fit_rms) +
                     " % of the diagonal from it (RMS; up to " + std::to_string(100 * opt.registered_rms) + " % is taken), 99th percentile " +
                     std::to_string(100 * d.fit_p99) + " % (up to " + std::to_string(100 * opt.registered_p99) +
                     " %); the transferred texture would be misplaced. Check that both models have the same branching, pin branches "
                     "with --match, or pass --force to write it anyway");
}

}  // namespace sdm
