#pragma once
/// Self-intersections of a triangle mesh: a model with one part pushed through another encodes
/// silently to a poor map, because a displacement map holds one surface per ray and the two
/// sheets inside each other cannot both be carried. The encoder names such input instead.
///
/// Pairs of faces that share no vertex are tested (faces with a common corner or edge meet there by
/// construction): candidate pairs from a bounding-volume hierarchy of the faces' boxes, then the
/// edges of each triangle against the other (segment-triangle tests, Moller & Trumbore 1997).
/// Coplanar overlaps are not reported.
#include <Eigen/Dense>

#include <array>
#include <vector>

namespace sdm {

struct SelfIntersections {
  long pairs = 0;                                   ///< intersecting face pairs (up to max_pairs)
  Eigen::Vector3d example = Eigen::Vector3d::Zero();  ///< a point where two faces cross
  int face_a = -1, face_b = -1;                     ///< the two faces of that example
};

/// V, F: a triangle mesh. Counts the pairs of faces without a common vertex that cross, stopping
/// at max_pairs.
SelfIntersections find_self_intersections(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, long max_pairs = 1000000);

/// Every crossing pair (f, g), f < g, as CGAL's PMP::self_intersections counts them (the measure of
/// the independent checker): pairs without a common vertex as above, and also pairs with exactly one
/// common vertex whose edges opposite it cross the other face (a fold through that vertex) and pairs
/// with a common edge folded flat onto each other (normals within 1e-4 of opposite). `faces`, when
/// given, restricts the pairs to those with at least one face flagged (the rest are not looked at).
std::vector<std::array<int, 2>> crossing_face_pairs(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                                    const std::vector<char>& faces = {});

/// The test of one pair of crossing_face_pairs: triangles A and B, whose corners are the points a
/// and b (indices: equal indices are a shared corner).
bool face_pair_crosses(const std::array<Eigen::Vector3d, 3>& A, const std::array<int, 3>& a, const std::array<Eigen::Vector3d, 3>& B,
                       const std::array<int, 3>& b);

}  // namespace sdm
