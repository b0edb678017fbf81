#pragma once
/// The dense correspondence between two models with the same skeleton branching, without GL
/// (DECISIONS 5): per target vertex the source point it shows. The target is recognised as the
/// source's shape (its skeleton carried over), the source in another pose (bent along its skeleton),
/// or another body (registered along its matched skeleton, every symmetric candidate match tried:
/// register_bodies), the source points under the placed source are mended where touching parts
/// made them jump, and a registered target's are refined in the Laplace-Beltrami eigenbases
/// (zoomout). One acceptance judge (judge_correspondence) turns what was measured into the refusals.
/// Texture transfer (transfer_texture) draws the atlas through this correspondence; `sdm correspond`
/// writes it.
#include "libstm/core/progress.h"
#include "libstm/correspondence/register_bodies.h"
#include "libstm/correspondence/share_skeletons.h"
#include "libstm/mesh/mesh.h"
#include "libstm/registration/carry_skeleton.h"
#include "libstm/registration/fit_skeleton.h"
#include "libstm/registration/register_surfaces.h"
#include "libstm/registration/zoomout.h"
#include "libstm/skeleton/skeleton.h"

#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sdm {

/// The correspondence's stages and thresholds. Distances are fractions of the target's bounding-box
/// diagonal; the measurements behind the thresholds are in docs/BENCHMARKS.md, "Thresholds: what they
/// rest on".
struct CorrespondOptions {
  double split_ratio = 2.0;                // share_skeletons
  std::vector<std::pair<int, int>> fixed;  // (source node, target node) key pairs that must match
  /// A target that is the source's shape (recognised_kind: registered by register_surfaces with an
  /// RMS distance under same_shape_rms and a 99th percentile under same_shape_p99; or under twice
  /// that RMS and no more than 1.5 times the bent fit's below) takes the source's skeleton carried
  /// over (carry_skeleton) instead of skeleton_b: two extractions of one shape differ with the
  /// tessellation, in node positions and even in small branches. Not done when `fixed` pairs are
  /// given (they name nodes of skeleton_b).
  bool carry_same_shape = true;
  double same_shape_rms = 0.005, same_shape_p99 = 0.02;
  /// Otherwise (same condition) the source's skeleton is bent onto the target (fit_skeleton): it is
  /// used when the bent source lies within fit_rms (RMS) and fit_p99 (99th percentile) of the
  /// target and no two ends came closer than fit_spread of their distance, unless the registration
  /// as another body below fits closer and would be taken (a raised leg of another person folds at
  /// the knee when bent). Both meshes must have the same Euler characteristic (genus) for either.
  double fit_rms = 0.004, fit_p99 = 0.016, fit_spread = 0.5;
  /// Otherwise, a target of another body with the same branching (another person or pose, an
  /// animal of the same kind) is registered: the source bent onto it along its skeleton from each
  /// of `candidates` matches of the extracted skeletons (register_bodies). A fit worse than
  /// registered_rms (RMS) or registered_p99 (99th percentile) is refused unless `force`.
  bool register_bodies = true;
  int candidates = 4;
  double registered_rms = 0.01, registered_p99 = 0.04;
  /// A match whose branches disagree in relative length by more than this factor
  /// (length_disagreement) is refused unless `force`: the surfaces then fit closely while the
  /// texture lands on other parts (a skeleton that lost its head).
  double registered_disagreement = 3.0;
  /// A match whose end branches meet the core (a torso) at places further apart on the two models
  /// than this fraction of the diagonal (BodyRegistration::attachment, after the best similarity)
  /// is refused unless `force`: limbs are paired with other limbs, which the non-rigid fit then
  /// bends into place. Not measured (0) where a model's core spans under 3 % of its skeleton.
  double registered_attachment = 0.05;
  /// A registration that would be taken but lays the attachments further apart than this is
  /// checked against the other extraction candidates (other_candidate) like a refused one, and
  /// kept unless another pair fits closer (a medial skeleton that joins an arm to the belly beside
  /// the hips lays the texture upside down).
  double marginal_attachment = 0.04;
  /// Likewise a registration that would be taken but changes the distances between the
  /// extremities by more than this share (BodyRegistration::distortion): a body of other
  /// proportions, where a skeleton that hangs a limb from another junction still lays its
  /// attachments close.
  double marginal_distortion = 0.25;
  /// When the given skeletons' branchings differ beyond small branches, or their matched branches
  /// disagree in length beyond registered_disagreement, so that the target (neither the source's
  /// shape nor the source bent) would be refused, each model's other extraction candidate is
  /// tried: other_candidate(false) for the source, other_candidate(true) for the target
  /// (std::nullopt: none, e.g. a skeleton the user gave; an InputError thrown: none either, the
  /// given pair's verdict stands). The pairs (a, b'), (a', b), (a', b') are all registered, and of
  /// those whose branchings agree (common_branching) and whose branches agree in length (or that
  /// would be taken, where the given pair's registration would be refused for another reason or is
  /// marginal) the one that fits closest is kept. An extraction keeps one of two candidates, and
  /// either can miss a major branch when the coordinates change in their last bits. Not tried with
  /// `fixed` pairs (they name nodes of the given skeletons).
  std::function<std::optional<Skeleton>(bool target)> other_candidate;
  /// A registered target's correspondence (closest points of the placed source) refined in the
  /// Laplace-Beltrami eigenbases of both models (zoomout; DECISIONS 5, "Spectral refinement"). Not
  /// done for a target carried or bent (the source's shape or pose), where the closest points are
  /// right.
  bool refine = true;
  ZoomOutOptions refinement;
  bool force = false;
  Progress progress;
};

/// What the correspondence found the target to be.
enum class CorrespondenceKind {
  skeleton_only,  // matched by the skeletons alone (the genera differ, or carry_same_shape is off): no points
  carried,        // the source's shape: the source's skeleton carried over
  bent,           // the source in another pose: the source's skeleton bent onto it
  registered,     // another body: the source registered along its matched skeleton
};

/// Which models an "other extraction candidate" names, in words: "source and the target", "source"
/// or "target" (CorrespondenceDiagnostics::other_source_candidate, other_target_candidate).
const char* other_candidates_named(bool source, bool target);

/// The kind in words: "skeleton only", "carried", "bent", "registered".
const char* kind_name(CorrespondenceKind kind);

/// What the source registered onto the target as a whole (`moved`) and bent along its skeleton
/// (`bent`; nullptr where it was not bent) say the target is (CorrespondOptions::carry_same_shape,
/// same_shape_rms, fit_rms): `carried` (the source's shape), `bent` (the source in another pose) or
/// else `skeleton_only` (another body, or nothing known yet). A measure that is not a number (NaN)
/// passes no threshold, so it never makes the target carried or bent.
CorrespondenceKind recognised_kind(const Registration& moved, const SkeletonFit* bent, const CorrespondOptions& opt);

/// What the stages measured, for the acceptance judge and the reports.
struct CorrespondenceDiagnostics {
  Registration registration;  // source onto target as a whole (when carry_same_shape was tried)
  double fit_rms = INFINITY, fit_p99 = INFINITY;  // bent or registered: the placed source's distances to the target
  /// Registered with a model's other extraction candidate (CorrespondOptions::other_candidate): the
  /// node numbers of `skeletons` then refer to that candidate.
  bool other_source_candidate = false, other_target_candidate = false;
  /// Another candidate match tied with the chosen one (BodyRegistration::ambiguity): left and right
  /// may be swapped.
  std::string ambiguity;
  std::vector<double> candidate_rms;  // per candidate match, the short registration's RMS (registered)
  std::vector<double> candidate_twist, candidate_distortion, candidate_attachment, candidate_bend;  // and BodyRegistration's other measures
  double distortion = 0;              // registered: BodyRegistration::distortion
  double attachment = 0;              // registered: BodyRegistration::attachment
  std::vector<BranchFit> branch_fit;  // registered: per branch
  bool refined = false;               // registered and refined (CorrespondOptions::refine)
  /// Registered: the symmetric rival taken through the whole fit (BodyRegistration::rival, 0-based;
  /// -1 none), both full fits' scores, and whether the rival was kept instead.
  int rival = -1;
  double final_score = NAN, rival_score = NAN;
  bool switched = false;
};

struct Correspondence {
  CorrespondenceKind kind = CorrespondenceKind::skeleton_only;
  SharedSkeletons skeletons;  // the matched skeletons resampled onto one graph
  /// Carried, bent or registered: per target vertex, the source point it shows (source face and
  /// barycentric coordinates), and per target face the source point under its centroid.
  std::vector<SourcePoint> points, face_points;
  /// Bent: per segment of skeletons.a, the rotation of the source's fitted node nearest it.
  std::vector<Eigen::Matrix3d> segment_rotation;
  CorrespondenceDiagnostics diagnostics;
};

/// The correspondence of `target` onto `source` (skeleton_a and skeleton_b extracted from them or
/// given).
/// \pre skeleton_a and skeleton_b have a node for every vertex of source and target.
/// \throw InputError where the skeletons' branchings differ (naming what differs and how far the
/// target is from the source's shape) or judge_correspondence refuses the result.
Correspondence correspond(const Mesh& source, const Skeleton& skeleton_a, const Mesh& target, const Skeleton& skeleton_b,
                          const CorrespondOptions& options = {});

/// The acceptance judge of a registered correspondence (the others pass), unless options.force.
/// \throw InputError, naming what was measured and how to go on, where the matched branches
/// disagree in length, meet the core at other places, tie between left and right (or front and
/// back), or fit poorly.
void judge_correspondence(const Correspondence& c, const CorrespondOptions& options);

}  // namespace sdm
