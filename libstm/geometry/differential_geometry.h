#pragma once
/// Small geometric helpers shared by every layer (pmp-library keeps the same kind of functions in
/// one differential_geometry.h): areas, barycentric coordinates, closest points on segments, the
/// rotation nearest to a matrix, similarity fits, and weighted statistics. Each is defined once,
/// here, so that two stages never disagree on a formula.
#include <Eigen/Dense>
#include <vector>

namespace sdm {

/// Area of the triangle a, b, c (half the norm of the edge cross product).
inline double triangle_area(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

/// Barycentric coordinates of p's projection onto the plane of triangle a, b, c (they sum to 1 and
/// are negative outside the triangle). A degenerate triangle gives (1, 0, 0).
Eigen::Vector3d barycentric(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c);

/// Distance from p to the closed segment a-b. `t`, when given, receives the unclamped parameter of
/// p's projection onto the line (0 at a, 1 at b; 0 when a == b).
double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           double* t = nullptr);

/// The rotation R nearest to M in the Frobenius norm (polar decomposition by SVD), reflections
/// excluded. With M = sum_i w_i y_i x_i^T (centred points), R is the rotation that best takes the
/// x_i onto the y_i (Kabsch). `trace`, when given, receives the sum of M's singular values with the
/// reflection's sign applied: the similarity scale is trace / sum_i w_i |x_i|^2, and
/// `second_singular`, when given, M's second singular value (near 0: the points lie on a line and R
/// is not determined by them).
Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& M, double* trace = nullptr, double* second_singular = nullptr);

/// p -> scale * rotation * p + translation.
struct Similarity {
  double scale = 1;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d operator()(const Eigen::Vector3d& p) const { return scale * (rotation * p) + translation; }
  Similarity inverse() const;
};

/// The similarity that minimises sum_i w_i |T(x_i) - y_i|^2 (Umeyama 1991). Identity when the
/// weights sum to zero; scale 1 when the x_i coincide.
Similarity fit_similarity(const std::vector<Eigen::Vector3d>& x, const std::vector<Eigen::Vector3d>& y,
                          const std::vector<double>& w);

/// The q-quantile (0 <= q <= 1) of `values` under `weights`: the smallest value whose cumulative
/// weight, in ascending order, reaches q times the total. 0 for an empty list.
double weighted_quantile(const std::vector<double>& values, const std::vector<double>& weights, double q);

}  // namespace sdm
