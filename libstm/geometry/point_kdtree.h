#pragma once
/// A k-d tree over a fixed set of 3-D points: the k nearest neighbours of a query and the points
/// within a radius, exact (the point-cloud stages: normals, the contraction's neighbourhood graph,
/// the nodes' sampling).
#include <Eigen/Dense>

#include <vector>

namespace sdm {

class PointKdTree {
 public:
  /// Builds the tree over `points` (kept by reference: they must outlive the tree, unchanged).
  explicit PointKdTree(const std::vector<Eigen::Vector3d>& points);
  /// The indices of the `k` points nearest to `q`, nearest first (fewer when there are fewer
  /// points); `squared`, when given, receives their squared distances. Ties go to the smaller index.
  std::vector<int> nearest(const Eigen::Vector3d& q, int k, std::vector<double>* squared = nullptr) const;
  /// The indices of the points within `radius` of `q` (in no particular order).
  std::vector<int> within(const Eigen::Vector3d& q, double radius) const;
  const std::vector<Eigen::Vector3d>& points() const { return points_; }

 private:
  struct Node {
    int begin = 0, end = 0;   ///< range of order_
    int axis = -1;            ///< -1: a leaf
    double split = 0;
    int left = -1, right = -1;
  };
  int build(int begin, int end);
  const std::vector<Eigen::Vector3d>& points_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

}  // namespace sdm
