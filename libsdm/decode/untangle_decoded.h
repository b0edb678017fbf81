#pragma once
/// Decoded points that fold the surface over itself where the input does not (DESIGN 4.8). Each
/// decoded point lies on the encoded surface, but two neighbouring points placed along directions
/// that differ (the rays of two segments at a base edge between them, or a direction field turning
/// faster than the displacement is small: concave places, thin parts) can land in the other order
/// on it, and their triangles then fold over and cross. A fold is local: its two faces come from one
/// base face or from base faces that share a corner. Where such a pair crosses, the displacements
/// (point minus its flat point on the base face) of its points and of the points one edge around
/// them are smoothed (Laplacian, Jacobi steps) and, if the pair still crosses, shrunk towards the
/// flat base, which folds nowhere (the base mesh is a decimation of the input), until no local pair
/// crosses. Pairs of faces far apart on the base mesh (two parts that touch in the input) are left
/// as they are.
#include <Eigen/Dense>

#include <vector>

namespace sdm {

struct UntangleReport {
  long crossing = 0;               ///< local crossing pairs before
  long left = 0;                   ///< local crossing pairs after (the rounds ran out)
  long moved = 0;                  ///< points moved
  std::vector<int> left_segments;  ///< the segments of the points of the pairs left, sorted, once each
};

/// points: the decoded points (changed in place); flat: each point's flat point; triangles and
/// triangle_face (the base face of each); base_triangles: the base mesh; point_segment: each point's
/// segment (for the report). Points whose displacement is 0 stay where they are.
UntangleReport untangle_decoded(std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& flat,
                                const Eigen::MatrixX3i& triangles, const std::vector<int>& triangle_face,
                                const Eigen::MatrixX3i& base_triangles, const std::vector<int>& point_segment);

}  // namespace sdm
