#pragma once
/// Articulated registration of a source surface onto a target driven by the source's skeleton: every
/// skeleton node carries a rigid motion, surface points follow the motions of the two nodes of the
/// skeleton edge they lie along (linear blend skinning, weights by the position along the edge), and
/// the motions are fitted by articulated iterative closest points (Pellegrini et al. 2008, Tagliasacchi's
/// articulated ICP; Pauly's "articulated ICP" course notes): closest points both ways, pairs whose
/// normals disagree by more than a set angle left out, each step a Gauss-Newton step on linearised
/// rotations with point-to-plane and point-to-point terms (Chen and Medioni 1992), neighbouring motions
/// held together at their joint (the points of each edge and a frame around it, as Sumner's E_reg
/// holds an embedded deformation together) and every node pulled towards its guessed place with a
/// weight that fades. Started from the similarity of the source's nodes onto their guesses and from
/// each node's edges turned onto the guesses' (a limb's twist is left to the closest points). The pose
/// found is then refined non-rigidly by fit_skeleton (embedded deformation, stiffness lowered step by
/// step), started where the articulated fit left the surface (or from the guesses, when that ends closer). The key-node correspondence must be
/// right: the registration follows the guesses and does not question them.
#include "libstm/geometry/differential_geometry.h"
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/skeleton.h"

#include <Eigen/Dense>
#include <cmath>
#include <vector>

namespace sdm {

struct ArticulatedOptions {
  int iterations = 30;            ///< articulated ICP steps (Gauss-Newton on closest pairs)
  double joint_weight = 0.1;      ///< neighbours' agreement at their joints, against the mean squared distance
  double guess_weight = 1.0;      ///< nodes towards their guesses: halved every `guess_halving` steps
  int guess_halving = 3;
  double guess_floor = 0.3;      ///< the guesses' weight never falls below this
  double plane_weight = 0.5;      ///< point-to-plane share of a pair's error (at most 0.9); point-to-point gets the rest
  double normal_angle = 60;       ///< degrees: pairs whose normals disagree by more are left out
  int stride = 1;                 ///< closest pairs of every stride-th vertex only, both ways (a quick screening)
  double outlier = 0.1;           ///< pairs further apart than this fraction of the target's diagonal are left out
  /// Refine non-rigidly (fit_skeleton) twice, from the articulated pose and from the guesses alone
  /// (fit_skeleton's own start), and keep the closer (smaller RMS distance): the articulated pose
  /// may leave a limb where the refinement cannot free it, and on other pairs it is the better start.
  bool refine = true;
};

struct ArticulatedFit {
  std::vector<Eigen::Vector3d> posed;     ///< the source's vertices after the articulated fit (target frame)
  std::vector<Eigen::Vector3d> deformed;  ///< after the non-rigid refinement (= posed without refine)
  std::vector<Similarity> node_motion;    ///< per node, source -> target under its rigid motion (global scale)
  Skeleton skeleton;                      ///< the source's graph with its nodes moved by their motions
  /// Distances between the posed / deformed source and the target, both ways, area-weighted, as
  /// fractions of the target's bounding-box diagonal.
  double posed_rms = INFINITY, rms = INFINITY, p99 = INFINITY;
  /// Mean angle, in degrees, between the rotations of neighbouring nodes after the articulated fit:
  /// a match with left and right (or front and back) swapped fits the surfaces about as closely, but
  /// only by turning some parts half around against their neighbours (register_bodies chooses by it).
  double twist = 0;
  bool refined_from_guesses = false;     ///< the refinement kept started from the guesses, not the pose
  int iterations = 0;
};

/// `skeleton` belongs to `source` (vertex_node has its vertex count); `node_guess` gives one place in
/// the target per node (a correct match of the skeletons: the registration trusts it). Returns the
/// source bent onto the target: `deformed` has the source's vertex order and faces, so
/// source_points_under(source, fit.deformed, target points) is the correspondence. The target may be
/// turned, moved and scaled against the source: the guesses carry that. Deterministic. Throws
/// InputError when vertex_node does not match the source, node_guess does not have one place per
/// node, or either mesh has no face.
ArticulatedFit articulated_registration(const Mesh& source, const Skeleton& skeleton, const Mesh& target,
                                        const std::vector<Eigen::Vector3d>& node_guess, const ArticulatedOptions& options = {});

}  // namespace sdm
