#pragma once
/// A k-d tree over a fixed set of 3-D points: the k nearest neighbours of a query and the points
/// within a radius, exact (the point-cloud stages: normals, the contraction's neighbourhood graph,
/// the nodes' sampling, the surface's implicit function). A query allocates nothing when it writes
/// into the caller's arrays; the points are kept in the leaves' order, each leaf's points side by side.
#include <Eigen/Dense>

#include <vector>

namespace sdm {

class PointKdTree {
 public:
  /// Builds the tree over `points` (copied: they need not outlive the tree).
  explicit PointKdTree(const std::vector<Eigen::Vector3d>& points);
  /// The indices of the `k` points nearest to `q`, nearest first (fewer when there are fewer
  /// points); `squared`, when given, receives their squared distances. Ties go to the smaller index.
  std::vector<int> nearest(const Eigen::Vector3d& q, int k, std::vector<double>* squared = nullptr) const;
  /// The same into `index` and `squared` (room for k each); returns how many were written.
  int nearest(const Eigen::Vector3d& q, int k, int* index, double* squared) const;
  /// The index of the point nearest to `q` (-1 when there are none), its squared distance in `squared`.
  int nearest_one(const Eigen::Vector3d& q, double* squared = nullptr) const;
  /// The indices of the points within `radius` of `q` (in no particular order).
  std::vector<int> within(const Eigen::Vector3d& q, double radius) const;
  int size() const { return int(order_.size()); }

 private:
  struct Node {
    int begin = 0, end = 0;   ///< range of order_
    int axis = -1;            ///< -1: a leaf
    double split = 0;
    int left = -1, right = -1;
  };
  int build(const std::vector<Eigen::Vector3d>& points, int begin, int end);
  std::vector<int> order_;
  std::vector<Eigen::Vector3d> leaf_points_;  ///< points[order_[i]]
  std::vector<Node> nodes_;
};

/// The mean distance from a point of `points` (those `tree` was built over) to its nearest other
/// point, over every `stride`-th point from the first (0 for a single point): a cloud's spacing.
double mean_nearest_distance(const std::vector<Eigen::Vector3d>& points, const PointKdTree& tree, int stride = 1);

}  // namespace sdm
