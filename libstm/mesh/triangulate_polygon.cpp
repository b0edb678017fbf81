#include "libstm/mesh/triangulate_polygon.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace sdm {
namespace {

using Vec2 = Eigen::Vector2d;

// The corners in the plane of the polygon's Newell normal, counter-clockwise seen from that normal.
std::vector<Vec2> project_polygon(const std::vector<Eigen::Vector3d>& corners) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  const size_t k = corners.size();
  for (size_t i = 0; i < k; ++i) {
    const Eigen::Vector3d& a = corners[i];
    const Eigen::Vector3d& b = corners[(i + 1) % k];
    n += Eigen::Vector3d((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()), (a.x() - b.x()) * (a.y() + b.y()));
  }
  if (n.norm() == 0 || !std::isfinite(n.norm())) n = Eigen::Vector3d::UnitZ();
  n.normalize();
  Eigen::Vector3d e1 = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  e1 = (e1 - n * n.dot(e1)).normalized();
  const Eigen::Vector3d e2 = n.cross(e1);  // e1 x e2 = n: counter-clockwise
  std::vector<Vec2> p(k);
  for (size_t i = 0; i < k; ++i) p[i] = Vec2(corners[i].dot(e1), corners[i].dot(e2));
  return p;
}

double cross(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}


class EarClipper {
 public:
  explicit EarClipper(std::vector<Vec2> p) : p_(std::move(p)), prev_(p_.size()), next_(p_.size()), key_(p_.size(), 0) {
    const int k = int(p_.size());
    Eigen::AlignedBox2d box;
    for (const Vec2& q : p_) box.extend(q);
    eps_ = 1e-12 * box.diagonal().squaredNorm();
    for (int i = 0; i < k; ++i) prev_[i] = (i + k - 1) % k, next_[i] = (i + 1) % k;
    left_ = k;
  }

  std::vector<std::array<int, 3>> run() {
    std::vector<std::array<int, 3>> out;
    rescan();
    int start = 0;
    while (left_ > 3) {
      if (ears_.empty() && (rescan(), ears_.empty())) break;  // degenerate: fan the rest
      const int i = ears_.begin()->second;
      out.push_back({prev_[i], i, next_[i]});
      start = next_[i];
      remove(i);
    }
    // The last triangle, or a fan of what no ear could cut.
    for (int a = start, b = next_[a]; next_[b] != a; b = next_[b]) out.push_back({a, b, next_[b]});
    return out;
  }

 private:
  bool convex(int i) const { return cross(p_[prev_[i]], p_[i], p_[next_[i]]) > eps_; }

  // Convex, and no reflex corner inside or on the triangle it cuts off.
  bool is_ear(int i) const {
    if (!convex(i)) return false;
    const Vec2 &a = p_[prev_[i]], &b = p_[i], &c = p_[next_[i]];
    for (int j : reflex_) {
      if (j == prev_[i] || j == i || j == next_[i]) continue;
      const Vec2& q = p_[j];
      if (cross(a, b, q) >= 0 && cross(b, c, q) >= 0 && cross(c, a, q) >= 0) return false;
    }
    return true;
  }

  void update(int i) {
    ears_.erase({key_[i], i});
    if (convex(i)) reflex_.erase(i); else reflex_.insert(i);
    if (!is_ear(i)) return;
    key_[i] = (p_[next_[i]] - p_[prev_[i]]).squaredNorm();
    ears_.insert({key_[i], i});
  }

  void rescan() {
    reflex_.clear();
    int i = first();
    for (int n = 0; n < left_; ++n, i = next_[i])
      if (!convex(i)) reflex_.insert(i);
    for (int n = 0; n < left_; ++n, i = next_[i]) update(i);
  }

  int first() const {
    for (int i = 0; i < int(p_.size()); ++i)
      if (next_[i] >= 0) return i;
    return 0;
  }

  void remove(int i) {
    ears_.erase({key_[i], i});
    reflex_.erase(i);
    const int a = prev_[i], b = next_[i];
    next_[a] = b, prev_[b] = a;
    prev_[i] = next_[i] = -1;
    --left_;
    update(a), update(b);
  }

  std::vector<Vec2> p_;
  std::vector<int> prev_, next_;
  std::vector<double> key_;
  std::set<std::pair<double, int>> ears_;  // (squared diagonal, corner): the shortest cut first
  std::set<int> reflex_;
  double eps_ = 0;
  int left_ = 0;
};

}  // namespace

std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<Eigen::Vector3d>& corners) {
  const int k = int(corners.size());
  if (k < 3) return {};
  if (k == 3) return {{0, 1, 2}};
  const std::vector<Vec2> p = project_polygon(corners);
  if (k == 4) {
    // The fan's diagonal 0-2 when it lies inside the quadrilateral (corners 1 and 3 on either side).
    if (cross(p[0], p[2], p[1]) < 0 && cross(p[0], p[2], p[3]) > 0) return {{0, 1, 2}, {0, 2, 3}};
    if (cross(p[1], p[3], p[2]) < 0 && cross(p[1], p[3], p[0]) > 0) return {{1, 2, 3}, {1, 3, 0}};
    return {{0, 1, 2}, {0, 2, 3}};  // degenerate: no diagonal is better
  }
  return EarClipper(p).run();
}

}  // namespace sdm
