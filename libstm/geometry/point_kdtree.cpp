#include "libstm/geometry/point_kdtree.h"

#include <algorithm>
#include <numeric>
#include <queue>
#include <utility>

namespace sdm {

namespace {
constexpr int kLeafSize = 12;
}  // namespace

PointKdTree::PointKdTree(const std::vector<Eigen::Vector3d>& points) : points_(points), order_(points.size()) {
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(2 * points.size() / kLeafSize + 2);
  if (!points.empty()) build(0, int(points.size()));
}

// Splits [begin, end) of order_ at the median of its widest axis.
int PointKdTree::build(int begin, int end) {
  const int id = int(nodes_.size());
  nodes_.push_back({begin, end, -1, 0, -1, -1});
  if (end - begin <= kLeafSize) return id;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (int i = begin; i < end; ++i) lo = lo.cwiseMin(points_[size_t(order_[size_t(i)])]), hi = hi.cwiseMax(points_[size_t(order_[size_t(i)])]);
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  if (!(hi[axis] > lo[axis])) return id;  // every point the same: one leaf
  const int mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](int a, int b) {
    return points_[size_t(a)][axis] < points_[size_t(b)][axis];
  });
  const double split = points_[size_t(order_[size_t(mid)])][axis];
  const int left = build(begin, mid);
  const int right = build(mid, end);
  Node& n = nodes_[size_t(id)];
  n.axis = axis, n.split = split, n.left = left, n.right = right;
  return id;
}

std::vector<int> PointKdTree::nearest(const Eigen::Vector3d& q, int k, std::vector<double>* squared) const {
  using Entry = std::pair<double, int>;  // squared distance, index: a max-heap of the best k
  std::priority_queue<Entry> best;
  k = std::min(k, int(points_.size()));
  if (k <= 0) return {};
  // Depth first, the nearer side first; a side is skipped when its slab is farther than the k-th.
  std::vector<std::pair<int, double>> stack{{0, 0.0}};
  while (!stack.empty()) {
    const auto [id, gap] = stack.back();
    stack.pop_back();
    if (int(best.size()) == k && gap > best.top().first) continue;
    const Node& n = nodes_[size_t(id)];
    if (n.axis < 0) {
      for (int i = n.begin; i < n.end; ++i) {
        const int p = order_[size_t(i)];
        const Entry e{(points_[size_t(p)] - q).squaredNorm(), p};
        if (int(best.size()) < k) best.push(e);
        else if (e < best.top()) best.pop(), best.push(e);
      }
      continue;
    }
    const double d = q[n.axis] - n.split;
    const int near = d < 0 ? n.left : n.right, far = d < 0 ? n.right : n.left;
    stack.push_back({far, std::max(gap, d * d)});
    stack.push_back({near, gap});
  }
  std::vector<int> out(best.size());
  std::vector<double> sq(best.size());
  for (size_t i = best.size(); i-- > 0;) out[i] = best.top().second, sq[i] = best.top().first, best.pop();
  if (squared) *squared = std::move(sq);
  return out;
}

std::vector<int> PointKdTree::within(const Eigen::Vector3d& q, double radius) const {
  std::vector<int> out;
  if (points_.empty()) return out;
  const double r2 = radius * radius;
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const Node& n = nodes_[size_t(stack.back())];
    stack.pop_back();
    if (n.axis < 0) {
      for (int i = n.begin; i < n.end; ++i)
        if ((points_[size_t(order_[size_t(i)])] - q).squaredNorm() <= r2) out.push_back(order_[size_t(i)]);
      continue;
    }
    const double d = q[n.axis] - n.split;
    if (d - radius <= 0) stack.push_back(n.left);
    if (d + radius >= 0) stack.push_back(n.right);
  }
  return out;
}

}  // namespace sdm
