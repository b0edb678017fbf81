#pragma once
/// Branch matching between two skeletons with the same branching (paper 1 and 5, DESIGN 4.9):
/// each skeleton is reduced to its key nodes (junctions and ends) and the chains of degree-2 nodes
/// between them; the reduced graphs are matched by an isomorphism whose symmetric ties are broken
/// by geometry: relative chain lengths first (articulation-invariant), then the residual after the
/// best rigid alignment (Kabsch) and the pose, in the models' own orientation or after aligning the
/// skeletons' cores (junctions and their chains' first pieces) when the orientations differ.
#include "libstm/skeleton/skeleton.h"

#include <string>
#include <utility>
#include <vector>

namespace sdm {

struct ReducedSkeleton {
  struct Chain {
    int from = -1, to = -1;   ///< key node indices (into `keys`); equal for a loop
    std::vector<int> nodes;   ///< skeleton nodes from `from` to `to`, ends included
    std::vector<int> edges;   ///< skeleton edges along it, in order
    double length = 0;
  };
  std::vector<int> keys;      ///< skeleton nodes of degree != 2 (one chosen node per pure cycle)
  std::vector<Chain> chains;
  std::vector<int> key_degree;
};

/// Deterministic for a given skeleton; a component that is a pure cycle gets one key node, the
/// node farthest from the component's centre (ties by coordinates), so the choice follows geometry.
ReducedSkeleton reduce_skeleton(const Skeleton& skeleton);

/// The share of a reduced skeleton's total chain length that lies on chains between two junctions
/// (its core: a torso's spine); 0 for a skeleton without chains. Under kCoreShare the junctions
/// nearly coincide: which branch hangs from which junction, and where the branches meet the core,
/// say nothing (a gorilla's head and arms, and legs, at junctions under 1 % of its length apart).
constexpr double kCoreShare = 0.03;
double core_share(const ReducedSkeleton& reduced);

/// What differs between two branchings, in words ("junction degrees 3 vs 4; ends 3 vs 4"), or
/// empty when they can match.
std::string branching_difference(const Skeleton& a, const Skeleton& b);

struct SkeletonMatch {
  ReducedSkeleton a, b;
  std::vector<int> key_a_to_b;                   ///< key of a -> key of b
  std::vector<std::pair<int, bool>> chain_a_to_b;  ///< chain of a -> (chain of b, reversed)
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< best rigid alignment of a onto b
  double cost = 0;        ///< pose-invariant shape cost of the chosen match (0 for congruent skeletons)
  double confidence = 1;  ///< 1 - (shape + pose cost) / the next candidate's; 1 when the match is unique
  long candidates = 0;                           ///< isomorphisms examined
};

/// `fixed`: pairs (skeleton node of a, skeleton node of b) that must match (key nodes only).
/// `same_orientation`: the two skeletons are given in roughly the same orientation (then their own
/// pose breaks ties between symmetric branches); false when one may be turned arbitrarily (then
/// each candidate is scored after the rotation aligning its cores: junctions and the first part
/// of their chains). Either way the relative chain lengths weigh most, so that an articulated limb
/// is not confused with a head (see the source for the measurements).
/// \throw InputError naming the difference when the branchings differ, or when a fixed pair is
/// not a pair of key nodes or cannot be satisfied.
SkeletonMatch match_skeletons(const Skeleton& a, const Skeleton& b, const std::vector<std::pair<int, int>>& fixed = {},
                              bool same_orientation = true);

/// How far the matched end branches disagree in length relative to their skeletons: the largest
/// ratio (>= 1) between the shares of the total chain length of an end branch of `m.a` and of its
/// match in `m.b`, over those with a share of at least `min_share` in either (chains between two
/// junctions are left out: where junctions fall varies between extractions, and a gorilla's arms
/// came out hung from a junction 0.5 % of the length from its pelvis's). Pose does not change
/// the shares, and two bodies of one kind keep them within a factor of about 1.5 (people, a
/// gorilla and a man); a match that pairs a leg with a head or an arm whose extracted
/// chain runs down the side of the torso gives 3 or more (DECISIONS 5, common branching).
double length_disagreement(const SkeletonMatch& m, double min_share = 0.05);

/// The candidates a registration chooses among (texture transfer between different bodies: which is
/// left and which right, front and back, only the surfaces tell): up to `count` matches with
/// distinct key maps, first the one match_skeletons(a, b, fixed, true) returns, then the best after
/// aligning the skeletons' cores (what match_skeletons(a, b, fixed, false) returns) and the next by
/// that score (for a person: the other assignments of left and right limbs).
/// \throw as
/// match_skeletons.
std::vector<SkeletonMatch> match_candidates(const Skeleton& a, const Skeleton& b, const std::vector<std::pair<int, int>>& fixed,
                                            int count);

}  // namespace sdm
