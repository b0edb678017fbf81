#pragma once
/// Front and back from the ends of two skeletons on one graph. A foot bends forward at
/// the ankle, whichever way the leg points, so the ends of a body bend the same way relative to its
/// core on two models matched the right way round, and the other way on a match with left and right
/// swapped: that match can only be laid by turning the core half around (front for back), and its
/// ends then bend backwards. The registration of a mirrored match fits the surfaces about as closely
/// (parts turned around to fit), so this is measured on the skeletons alone.
#include "libstm/skeleton/skeleton.h"

#include <Eigen/Dense>
#include <vector>

namespace sdm {

/// The bend of the end of the chain `path` (node indices from an end node to the key node where the
/// chain begins) in `nodes`: the component of the direction of the chain's last 15 % (by length)
/// across the direction of the 30 % before it. Its length is the sine of the bend's angle (near 1
/// for a foot, near 0 for a straight limb); zero for a chain of no length.
Eigen::Vector3d end_bend(const std::vector<Eigen::Vector3d>& nodes, const std::vector<int>& path);

/// `a` and `b` share one graph (a match resampled onto it, share_skeletons: node k of a corresponds
/// to node k of b). Per end node, the bend of its chain in a, turned by the rotation that best lays
/// a's core onto b's (the chains' key nodes and the points 15 % along each end chain from them: where
/// the limbs leave the torso, which a limb's pose hardly moves), against its bend in b: the sum over
/// the ends of the dot products. Positive when the ends bend alike (bodies matched the right way),
/// lower for the same bodies with left and right swapped (docs/BENCHMARKS.md, "Thresholds:
/// what they rest on"). 0 with fewer than three end chains (the core's rotation is not defined).
double end_bend_agreement(const Skeleton& a, const Skeleton& b);

}  // namespace sdm
