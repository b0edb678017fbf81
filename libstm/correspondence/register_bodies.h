#pragma once
/// The source bent onto a target of another body with the same skeleton branching (another person,
/// the same person in another pose, an animal of the same kind): the correspondence behind texture
/// transfer between different models (paper 1 and 5). Both extracted skeletons are reduced
/// to their common branching, and every candidate match of them (match_candidates: which limb is
/// left and which right, which side is the front, only the surfaces tell) drives a short articulated
/// registration of the source onto the target (articulated_registration: per-node rigid motions, the
/// match's resampled target chains as the nodes' guesses); among those whose ends bend about as alike
/// as the most alike (end_bend_agreement: front and back), the one whose parts turn least against
/// their neighbours, that fits closest and lays the places where the limbs meet the torso least apart
/// (one score) is kept, and its nodes start the non-rigid fit of the source's skeleton onto the
/// target (fit_skeleton: embedded deformation on the skeleton, stiffness lowered step by step). The
/// placed source gives every target point its source point (source_points_under).
#include "libstm/core/progress.h"
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/skeleton.h"
#include "libstm/correspondence/share_skeletons.h"

#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace sdm {

/// How closely one branch of the source (a chain between two key nodes, numbered as in the given
/// source skeleton) lies on the target after the registration.
struct BranchFit {
  int source_from = -1, source_to = -1;
  double rms = 0, p99 = 0;  // fractions of the target's bounding-box diagonal
  int vertices = 0;         // source vertices on the branch
};

struct BodyOptions {
  double split_ratio = 2.0;  // share_skeletons
  int candidates = 4;        // candidate matches tried (match_candidates)
  bool fit_rival = true;     // the symmetric rival also fitted, the closer kept or a tie reported
  Progress progress;
};

struct BodyRegistration {
  SharedSkeletons skeletons;            // the chosen match, both skeletons resampled onto one graph
  std::vector<Eigen::Vector3d> placed;  // the source's vertices bent onto the target (source order)
  /// Distances between the placed source and the target (closest points both ways, area-weighted),
  /// fractions of the target's diagonal.
  double rms = INFINITY, p99 = INFINITY;
  std::vector<double> candidate_rms;    // per candidate match, the RMS of its short articulated registration
  std::vector<double> candidate_twist;  // and its ArticulatedFit::twist (degrees)
  /// and how much it changes the distances along the surface between the source's extremities
  /// (ends of its skeleton), each over the square root of its surface's area: sum of |changes| over
  /// sum of distances (reported; the choice no longer uses it: a tip lands wherever parts touch).
  std::vector<double> candidate_distortion;
  /// and how far its end branches meet the core (a torso) at other places on the two models (RMS
  /// distance after the best similarity, fraction of the target's diagonal): a match that crosses one
  /// pair of limbs and keeps the others cannot lay the attachments together.
  std::vector<double> candidate_attachment;
  /// and how alike its ends bend relative to the core on the two models (end_bend_agreement): a match
  /// with front and back the other way bends them the other way.
  std::vector<double> candidate_bend;
  double distortion = 0;  // the same for the chosen registration
  /// candidate_attachment of the chosen match; 0 when a model's core (the chains between its
  /// junctions) spans under 3 % of its skeleton's length, so that its attachments all surround one
  /// point and do not compare (not measured).
  double attachment = 0;
  int chosen = 0;                       // the candidate chosen
  /// Set when another candidate that sends the source's ends to other target ends (left and right,
  /// or front and back, the other way) ties with the chosen one (twist and fit within kTieTwist and
  /// kTieFit, or scores within kScoreTie, of register_bodies.cpp): which one is right is then a
  /// guess. Names both (1-based) and their figures.
  std::string ambiguity;
  std::vector<BranchFit> branch_fit;  // per chain of the chosen match
  /// The symmetric rival taken through the whole fit (BodyOptions::fit_rival, DECISIONS 5 "Symmetric
  /// candidates"): the best-scoring candidate that sends the source's ends to other target ends, -1
  /// when none. final_score and rival_score: the twist of the fitted nodes (mean angle between
  /// neighbours' rotations, degrees) times the fit's RMS to the power 3/4, of the kept fit and of
  /// the rival's (NaN when not fitted). `switched`: the rival scored lower and was kept instead.
  int rival = -1;
  double final_score = NAN, rival_score = NAN;
  bool switched = false;
};

/// `skeleton_a` and `skeleton_b` belong to source and target (vertex_node of their vertex counts);
/// `fixed` names key node pairs of them that must match (`sdm transfer --match`). Deterministic.
/// Throws InputError when the branchings differ beyond small branches (common_branching) or a
/// skeleton does not fit its mesh. It does not judge the fit: the caller reads rms and p99.
BodyRegistration register_bodies(const Mesh& source, const Skeleton& skeleton_a, const Mesh& target, const Skeleton& skeleton_b,
                                 const std::vector<std::pair<int, int>>& fixed, const BodyOptions& options = {});

}  // namespace sdm
