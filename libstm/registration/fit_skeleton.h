#pragma once
/// A skeleton fitted onto a deformed copy of its model: the source's surface is bent onto the
/// target by the skeleton itself, used as the deformation graph of an embedded deformation (Sumner
/// et al. 2007) fitted by non-rigid iterative closest points (Amberg et al. 2007: stiffness lowered
/// step by step). Every node carries an affine map near a rotation times a scale; a surface point
/// follows the two nodes of the skeleton edge it lies along, blended linearly, so a limb bends at
/// its nodes and may thicken. The fitted nodes are the target's skeleton, with the source's
/// branching by construction; texture transfer uses them when the target is a reposed or reshaped
/// source, where an extracted skeleton can differ in branches and in where the nodes fall.
#include "libstm/mesh/mesh.h"
#include "libstm/registration/register_surfaces.h"
#include "libstm/skeleton/skeleton.h"

#include <Eigen/Dense>
#include <cmath>
#include <vector>

namespace sdm {

struct FitSkeletonOptions {
  /// Weight of the neighbours' agreement (Sumner's E_reg) against the mean squared distance of the
  /// surfaces: stiffness_start, halved stage by stage down to the first value at or below
  /// stiffness_end (1 -> 0.01: eight stages, the last at 1/128). A stage ends early when a step
  /// moves no node's translation by 1e-7 of the diagonal.
  double stiffness_start = 1.0, stiffness_end = 0.01;
  int iterations_per_stiffness = 6;
  /// Weight of |A - s R|^2 per node (R the rotation nearest to A, s its mean singular value clamped
  /// to [0.2, 5]): keeps the maps near rotations times a scale.
  double rigidity = 0.1;
  bool articulated_start = true;  ///< without node_guess: every node's neighbourhood first registered on its own
  /// The fitting steps pair every stride-th vertex of either surface (the final measures pair all).
  int stride = 1;
  double outlier = 0.1;    ///< closest-point pairs further apart than this fraction of the diagonal are left out
  /// With node_guess: per node, the rotation its first map takes (source frame -> target frame, as
  /// SkeletonFit::node_rotation) instead of the smallest rotation of its edges onto the guess's.
  /// Ignored unless it has one rotation per node.
  std::vector<Eigen::Matrix3d> start_rotations;
};

struct SkeletonFit {
  Skeleton skeleton;                  ///< the source's graph in the target; vertex_node for the target's vertices
  std::vector<Eigen::Matrix3d> node_rotation;  ///< per node, the rotation of its fitted map (start included)
  std::vector<Eigen::Vector3d> bent;  ///< the source's vertices bent onto the target
  /// Distances between the bent source and the target, as register_surfaces reports them.
  double rms = INFINITY, p99 = INFINITY;
  /// Area of the bent source over the target's: near 1 when the source covers the target once;
  /// limbs squeezed together onto one of the target (another branching) raise it.
  double area_ratio = 0;
  /// The smallest ratio, over pairs of end nodes, of their distance after the fit to their distance
  /// before (the start's scale included): a pose moves ends apart or together by some, but limbs
  /// squeezed onto one limb of the target (another branching) bring their ends together.
  double end_spread = 1;
  int iterations = 0;  ///< non-rigid steps completed, over every stage
};

/// `skeleton` belongs to `source` (vertex_node has its vertex count). `start` registers source onto
/// target as a whole (register_surfaces). `node_guess`, when it has one position per node, gives a
/// first place in the target for every node (e.g. the matched extracted skeleton of the target,
/// skeleton_onto_graph), from which each node's first map is taken; otherwise (a guess of another
/// size is ignored) each node's neighbourhood is first registered by a similarity of its own
/// (articulated_start). Each fitted node is placed by the similarity that best moves the vertices
/// it carries to where the fit bent them (by its own map when it carries fewer than three). Every
/// target vertex takes the node of the corner of largest barycentric weight of its closest point
/// on the bent source (vertex_nodes_through); a node left without a vertex takes the target vertex
/// nearest to its fitted place from a node that owns more than one. Deterministic. Throws
/// InputError when vertex_node does not match the source.
SkeletonFit fit_skeleton(const Mesh& source, const Skeleton& skeleton, const Mesh& target, const Similarity& start,
                         const std::vector<Eigen::Vector3d>& node_guess = {}, const FitSkeletonOptions& options = {});

}  // namespace sdm
