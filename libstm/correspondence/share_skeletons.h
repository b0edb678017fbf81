#pragma once
/// Two skeletons with the same branching resampled onto one graph (paper 1 and 5, DESIGN 4.9): the
/// skeletons' branches are matched (match_skeletons) and matched chains are resampled to the same
/// number of segments, so that the source's layout (its STM) can serve the target. Also the geometry
/// counterpart (a skeleton resampled onto another's graph, for decoding an SDM around it) and the
/// node pairs a user forces (`sdm transfer --match`).
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/match_skeletons.h"
#include "libstm/skeleton/skeleton.h"

#include <Eigen/Dense>
#include <string>
#include <utility>
#include <array>
#include <vector>

namespace sdm {

/// Two skeletons resampled onto one graph: a and b have the same node count and the same edge list,
/// so edge i of a corresponds to edge i of b, in the same direction. Node k of both is key k of the
/// match's reduced a (key_a_to_b[k] in b) for k < keys; then every chain's inner nodes, in order.
struct SharedSkeletons {
  Skeleton a, b;
  SkeletonMatch match;
  std::vector<std::vector<int>> chain_edges;  // per chain of match.a: its edges in the shared graph, in order
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // best rotation of a's shared nodes onto b's
  /// common_branching: end nodes of the given skeletons whose short branches were pruned so that the
  /// branchings match, and match.a's / match.b's node numbering -> the given skeletons' nodes.
  std::vector<int> pruned_a, pruned_b, node_a, node_b;
  std::vector<std::array<int, 3>> slid_a, slid_b;  // CommonBranching::slid_a / slid_b
  double length_disagreement = 1;                  // CommonBranching::length_disagreement
  /// share_skeletons_candidates: a's common branching had a pair of branches exchanged between two
  /// close junctions (exchanged_branches), so its resampled first edges cross from one to the other.
  bool exchanged = false;
};

/// Reduces a and b to their common branching (common_branching, its defaults: small end branches
/// pruned, short chains between junctions contracted, or a branch slid to a neighbouring junction,
/// up to 8 changes; `fixed` names nodes of the given skeletons), matches b to a
/// (match_skeletons with the `fixed` key node pairs) and resamples every matched pair
/// of chains at equal arc-length steps into n segments: n = the larger of the two chains' edge counts,
/// raised so that no segment of either model is longer than split_ratio times the chain's mean
/// radius (as LayoutOptions::split_ratio; <= 0: no such rule). Key nodes keep their positions.
/// A pure cycle (a ring with no junction) has no natural start: b's ring is restarted at the point
/// nearest to a's start placed on b by centres and sizes (the same pose assumed), as the ring's turn
/// about its axis cannot be told from shape. `rotation` is then fitted to the shared nodes.
/// Every vertex is reassigned by projecting it onto the chain of the nearest edge at its old node
/// (arc-length position, rounded to the nearest new node); a node left without vertices takes the
/// vertex of its chain nearest to it in arc length from a node that has more than one.
/// \throw InputError naming the difference when the branchings differ, or when a skeleton does not
/// fit its mesh.
SharedSkeletons share_skeletons(const Mesh& mesh_a, const Skeleton& a, const Mesh& mesh_b, const Skeleton& b,
                                const std::vector<std::pair<int, int>>& fixed = {}, double split_ratio = 2.0);

/// share_skeletons through each of match_candidates(count) of the common branching: the candidates a
/// registration of the surfaces chooses among (left and right limbs of a person turned around).
std::vector<SharedSkeletons> share_skeletons_candidates(const Mesh& mesh_a, const Skeleton& a, const Mesh& mesh_b, const Skeleton& b,
                                                        const std::vector<std::pair<int, int>>& fixed, double split_ratio, int count);

/// The shared skeletons' match with its key nodes (match.a.keys, match.b.keys) numbered as in the
/// skeletons given to share_skeletons, through node_a and node_b, instead of the pruned skeletons'
/// numbering; everything else as in shared.match (chains' node and edge lists stay pruned). The
/// same when nothing was pruned.
SkeletonMatch match_in_given_numbering(const SharedSkeletons& shared);

/// The geometry counterpart (decoding an SDM around another skeleton): `target` matched to `graph`
/// (match_skeletons(graph, target, fixed)) and resampled onto graph's own nodes and edges: key nodes
/// take the matched target key's position, every inner node of a chain the point of the matched
/// target chain at the same arc-length fraction. The result has graph's node count and edge list
/// (so decode_sdm's DecodeOptions::skeleton accepts it) and no vertex_node. `match`, when given,
/// receives the match. \throw InputError naming the difference when the branchings differ.
Skeleton skeleton_onto_graph(const Skeleton& graph, const Skeleton& target, const std::vector<std::pair<int, int>>& fixed = {},
                             SkeletonMatch* match = nullptr);

/// Node pairs forced to correspond, from "SOURCE_NODE=TARGET_NODE" texts (`sdm transfer --match`),
/// in order: two decimal integers around one '=', nothing else (std::stoi's leading blanks and
/// sign are allowed). Whether the nodes exist is left to match_skeletons. \throw InputError naming
/// the text that is not such a pair.
std::vector<std::pair<int, int>> parse_node_pairs(const std::vector<std::string>& items);

}  // namespace sdm
