#include "libstm/geometry/point_kdtree.h"

#include "libstm/core/parallel.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace sdm {

namespace {
constexpr int kLeafSize = 12;
// A median split halves every range, so the depth stays under 32 for any int-sized set, and a
// depth-first walk holds at most one pending far side per level.
constexpr int kMaxStack = 64;
}  // namespace

PointKdTree::PointKdTree(const std::vector<Eigen::Vector3d>& points) : order_(points.size()) {
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(2 * points.size() / kLeafSize + 2);
  if (!points.empty()) build(points, 0, int(points.size()));
  leaf_points_.resize(points.size());
  for (size_t i = 0; i < order_.size(); ++i) leaf_points_[i] = points[size_t(order_[i])];
}

// Splits [begin, end) of order_ at the median of its widest axis.
int PointKdTree::build(const std::vector<Eigen::Vector3d>& points, int begin, int end) {
  const int id = int(nodes_.size());
  nodes_.push_back({begin, end, -1, 0, -1, -1});
  if (end - begin <= kLeafSize) return id;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (int i = begin; i < end; ++i) lo = lo.cwiseMin(points[size_t(order_[size_t(i)])]), hi = hi.cwiseMax(points[size_t(order_[size_t(i)])]);
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  if (!(hi[axis] > lo[axis])) return id;  // every point the same: one leaf
  const int mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](int a, int b) {
    return points[size_t(a)][axis] < points[size_t(b)][axis];
  });
  const double split = points[size_t(order_[size_t(mid)])][axis];
  const int left = build(points, begin, mid);
  const int right = build(points, mid, end);
  Node& n = nodes_[size_t(id)];
  n.axis = axis, n.split = split, n.left = left, n.right = right;
  return id;
}

// The best k so far sorted by (squared distance, index) in the caller's arrays, depth first, the
// nearer side first; a side is skipped when its slab is farther than the k-th.
int PointKdTree::nearest(const Eigen::Vector3d& q, int k, int* index, double* squared) const {
  k = std::min(k, int(order_.size()));
  if (k <= 0) return 0;
  int m = 0;
  std::pair<int, double> stack[kMaxStack];
  int top = 0;
  stack[top++] = {0, 0.0};
  while (top > 0) {
    const auto [id, gap] = stack[--top];
    if (m == k && gap > squared[k - 1]) continue;
    const Node& n = nodes_[size_t(id)];
    if (n.axis < 0) {
      for (int i = n.begin; i < n.end; ++i) {
        const double d = (leaf_points_[size_t(i)] - q).squaredNorm();
        const int p = order_[size_t(i)];
        if (m == k && (d > squared[k - 1] || (d == squared[k - 1] && p > index[k - 1]))) continue;
        int j = m < k ? m++ : k - 1;
        for (; j > 0 && (squared[j - 1] > d || (squared[j - 1] == d && index[j - 1] > p)); --j)
          squared[j] = squared[j - 1], index[j] = index[j - 1];
        squared[j] = d, index[j] = p;
      }
      continue;
    }
    const double d = q[n.axis] - n.split;
    const int near = d < 0 ? n.left : n.right, far = d < 0 ? n.right : n.left;
    stack[top++] = {far, std::max(gap, d * d)};
    stack[top++] = {near, gap};
  }
  return m;
}

std::vector<int> PointKdTree::nearest(const Eigen::Vector3d& q, int k, std::vector<double>* squared) const {
  k = std::max(0, std::min(k, int(order_.size())));
  std::vector<int> out(size_t(k), 0);
  std::vector<double> sq(size_t(k), 0.0);
  nearest(q, k, out.data(), sq.data());
  if (squared) *squared = std::move(sq);
  return out;
}

int PointKdTree::nearest_one(const Eigen::Vector3d& q, double* squared) const {
  int index = -1;
  double d = 0;
  nearest(q, 1, &index, &d);
  if (squared) *squared = d;
  return index;
}

std::vector<int> PointKdTree::within(const Eigen::Vector3d& q, double radius) const {
  std::vector<int> out;
  if (order_.empty()) return out;
  const double r2 = radius * radius;
  int stack[kMaxStack];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[size_t(stack[--top])];
    if (n.axis < 0) {
      for (int i = n.begin; i < n.end; ++i)
        if ((leaf_points_[size_t(i)] - q).squaredNorm() <= r2) out.push_back(order_[size_t(i)]);
      continue;
    }
    const double d = q[n.axis] - n.split;
    if (d - radius <= 0) stack[top++] = n.left;
    if (d + radius >= 0) stack[top++] = n.right;
  }
  return out;
}

double mean_nearest_distance(const std::vector<Eigen::Vector3d>& points, const PointKdTree& tree, int stride) {
  stride = std::max(stride, 1);
  const int measured = (int(points.size()) + stride - 1) / stride;
  std::vector<double> d(size_t(std::max(measured, 0)), 0.0);
  parallel_for(measured, 1024, [&](int k) {
    int index[2];
    double squared[2];
    if (tree.nearest(points[size_t(k) * size_t(stride)], 2, index, squared) == 2) d[size_t(k)] = std::sqrt(squared[1]);
  });
  return std::accumulate(d.begin(), d.end(), 0.0) / double(std::max(measured, 1));
}

}  // namespace sdm
