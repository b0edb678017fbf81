#include "libstm/mesh/grouped_crossings.h"

#include "libstm/core/parallel.h"
#include "libstm/mesh/self_intersections.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace sdm {
namespace {

constexpr int kLeafSize = 4;

// Nodes of a tree over n faces: the build halves ranges until they fit a leaf.
int subtree_nodes(int n) { return n <= kLeafSize ? 1 : 1 + subtree_nodes(n / 2) + subtree_nodes(n - n / 2); }

// Closed boxes that meet; the six comparisons joined without branches (which way they go is a coin
// toss near the surface, and a mispredicted branch cost more than the rest of the test).
template <class A, class B>
bool boxes_meet(const A& alo, const A& ahi, const B& blo, const B& bhi) {
  return !((alo[0] > bhi[0]) | (alo[1] > bhi[1]) | (alo[2] > bhi[2]) | (ahi[0] < blo[0]) | (ahi[1] < blo[1]) | (ahi[2] < blo[2]));
}

// A float at or below x (at or above: up), so that a node's float box holds its faces' boxes.
float down(double x) {
  const float f = float(x);
  return double(f) > x ? std::nextafter(f, -INFINITY) : f;
}
float up(double x) {
  const float f = float(x);
  return double(f) < x ? std::nextafter(f, INFINITY) : f;
}

}  // namespace

GroupedCrossings::GroupedCrossings(const Eigen::MatrixX3i& F, const std::vector<int>& face_group, std::vector<std::vector<int>> near,
                                   const std::vector<Eigen::Vector3d>& points)
    : near_(std::move(near)) {
  const size_t groups = near_.size(), n = size_t(F.rows());
  group_start_.assign(groups + 1, 0);
  for (size_t f = 0; f < n; ++f) ++group_start_[size_t(face_group[f]) + 1];
  for (size_t g = 0; g < groups; ++g) group_start_[g + 1] += group_start_[g];
  order_.resize(n);
  std::vector<int> fill(group_start_.begin(), group_start_.end() - 1);
  for (size_t f = 0; f < n; ++f) order_[size_t(fill[size_t(face_group[f])]++)] = int(f);
  std::vector<Eigen::Vector3d> centre(n);
  for (size_t f = 0; f < n; ++f) centre[f] = points[size_t(F(Eigen::Index(f), 0))] + points[size_t(F(Eigen::Index(f), 1))] + points[size_t(F(Eigen::Index(f), 2))];
  root_.assign(groups, -1);
  int nodes = 0;
  for (size_t g = 0; g < groups; ++g)
    if (group_start_[g + 1] > group_start_[g]) root_[g] = nodes, nodes += subtree_nodes(group_start_[g + 1] - group_start_[g]);
  nodes_.resize(size_t(nodes));
  flagged_.assign(size_t(nodes), 0);
  parallel_for(int(groups), 64, [&](int g) {
    if (root_[size_t(g)] >= 0) build(group_start_[size_t(g)], group_start_[size_t(g) + 1], root_[size_t(g)], centre);
  });
  corner_.resize(n);
  for (size_t k = 0; k < n; ++k) corner_[k] = {F(order_[k], 0), F(order_[k], 1), F(order_[k], 2)};
  lo_.resize(n);
  hi_.resize(n);
}

// The subtree over order_[begin, end) into nodes_[index...] (preorder: the first child follows its
// parent), split at the median centre along the centres' longest extent; returns one past its last node.
int GroupedCrossings::build(int begin, int end, int index, const std::vector<Eigen::Vector3d>& centre) {
  Node& node = nodes_[size_t(index)];
  node.begin = begin, node.end = end;
  if (end - begin <= kLeafSize) return index + 1;
  Eigen::Vector3d lo = centre[size_t(order_[size_t(begin)])], hi = lo;
  for (int k = begin; k < end; ++k) lo = lo.cwiseMin(centre[size_t(order_[size_t(k)])]), hi = hi.cwiseMax(centre[size_t(order_[size_t(k)])]);
  int axis;
  (hi - lo).maxCoeff(&axis);
  const int mid = (begin + end) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](int x, int y) {
    const double cx = centre[size_t(x)][axis], cy = centre[size_t(y)][axis];
    return cx < cy || (cx == cy && x < y);
  });
  const int right = build(begin, mid, index + 1, centre);
  nodes_[size_t(index)].right = right;
  return build(mid, end, right, centre);
}

// The boxes of group g's faces and nodes at `points`, and which nodes hold a flagged face.
void GroupedCrossings::refit(int group, const std::vector<Eigen::Vector3d>& points, const std::vector<char>& faces) {
  const size_t g = size_t(group);
  for (int k = group_start_[g]; k < group_start_[g + 1]; ++k) {
    const auto& c = corner_[size_t(k)];
    const Eigen::Vector3d &a = points[size_t(c[0])], &b = points[size_t(c[1])], &d = points[size_t(c[2])];
    lo_[size_t(k)] = a.cwiseMin(b).cwiseMin(d), hi_[size_t(k)] = a.cwiseMax(b).cwiseMax(d);
  }
  const int first = root_[g], last = first + subtree_nodes(group_start_[g + 1] - group_start_[g]);
  for (int i = last - 1; i >= first; --i) {  // children after their parent: fitted before it
    Node& node = nodes_[size_t(i)];
    if (node.right < 0) {
      Eigen::Vector3d lo = lo_[size_t(node.begin)], hi = hi_[size_t(node.begin)];
      char flag = 0;
      for (int k = node.begin; k < node.end; ++k) {
        lo = lo.cwiseMin(lo_[size_t(k)]), hi = hi.cwiseMax(hi_[size_t(k)]);
        if (!faces.empty()) flag |= faces[size_t(order_[size_t(k)])];
      }
      for (int c = 0; c < 3; ++c) node.lo[c] = down(lo[c]), node.hi[c] = up(hi[c]);
      flagged_[size_t(i)] = flag;
    } else {
      const Node &l = nodes_[size_t(i) + 1], &r = nodes_[size_t(node.right)];
      node.lo = l.lo.cwiseMin(r.lo), node.hi = l.hi.cwiseMax(r.hi);
      flagged_[size_t(i)] = flagged_[size_t(i) + 1] | flagged_[size_t(node.right)];
    }
  }
}

// The crossing pairs between groups g and h (within g when h == g), tree against tree.
void GroupedCrossings::search(int g, int h, const std::vector<Eigen::Vector3d>& points, const std::vector<char>& faces,
                              const std::vector<char>& look, std::vector<std::array<int, 2>>& out) const {
  const bool all = faces.empty();
  // Whether the pairs below node i (of group `group`) may be wanted: flags are current in the groups refitted.
  auto flagged = [&](int i, int group) { return all || (look[size_t(group)] && flagged_[size_t(i)]); };
  auto test = [&](int i, int j) {
    const int f = order_[size_t(i)], e = order_[size_t(j)];
    if (!all && !faces[size_t(f)] && !faces[size_t(e)]) return;
    if (!boxes_meet(lo_[size_t(i)], hi_[size_t(i)], lo_[size_t(j)], hi_[size_t(j)])) return;
    const auto &a = corner_[size_t(i)], &b = corner_[size_t(j)];
    const std::array<Eigen::Vector3d, 3> A = {points[size_t(a[0])], points[size_t(a[1])], points[size_t(a[2])]};
    const std::array<Eigen::Vector3d, 3> B = {points[size_t(b[0])], points[size_t(b[1])], points[size_t(b[2])]};
    if (face_pair_crosses(A, a, B, b)) out.push_back({std::min(f, e), std::max(f, e)});
  };
  std::vector<std::pair<int, int>> stack = {{root_[size_t(g)], root_[size_t(h)]}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    const Node &a = nodes_[size_t(i)], &b = nodes_[size_t(j)];
    if (!flagged(i, g) && !flagged(j, h)) continue;
    if (i == j) {  // one node against itself
      if (a.right < 0) {
        for (int k = a.begin; k < a.end; ++k)
          for (int l = k + 1; l < a.end; ++l) test(k, l);
      } else {
        stack.push_back({i + 1, i + 1}), stack.push_back({a.right, a.right}), stack.push_back({i + 1, a.right});
      }
      continue;
    }
    if (!boxes_meet(a.lo, a.hi, b.lo, b.hi)) continue;
    if (a.right < 0 && b.right < 0) {
      for (int k = a.begin; k < a.end; ++k)
        if (boxes_meet(lo_[size_t(k)], hi_[size_t(k)], b.lo, b.hi))
          for (int l = b.begin; l < b.end; ++l) test(k, l);
    } else if (b.right < 0 || (a.right >= 0 && a.end - a.begin >= b.end - b.begin)) {
      stack.push_back({i + 1, j}), stack.push_back({a.right, j});
    } else {
      stack.push_back({i, j + 1}), stack.push_back({i, b.right});
    }
  }
}

std::vector<std::array<int, 2>> GroupedCrossings::find(const std::vector<Eigen::Vector3d>& points, const std::vector<char>& faces) {
  const int groups = int(near_.size());
  // A group is looked at when it holds a flagged face (every group without `faces`).
  std::vector<char> look(size_t(groups), faces.empty() ? 1 : 0);
  if (!faces.empty())
    for (int g = 0; g < groups; ++g)
      for (int k = group_start_[size_t(g)]; k < group_start_[size_t(g) + 1] && !look[size_t(g)]; ++k) look[size_t(g)] = faces[size_t(order_[size_t(k)])];
  parallel_for(groups, 64, [&](int g) {
    if (root_[size_t(g)] >= 0 && (first_ || look[size_t(g)])) refit(g, points, faces);
  });
  first_ = false;
  // Each pair of near groups once, from the lower; per group its pairs, on every core.
  std::vector<std::vector<std::array<int, 2>>> found(static_cast<size_t>(groups));
  parallel_for(groups, 16, [&](int g) {
    for (int h : near_[size_t(g)])
      if (h >= g && root_[size_t(g)] >= 0 && root_[size_t(h)] >= 0 && (look[size_t(g)] || look[size_t(h)]))
        search(g, h, points, faces, look, found[size_t(g)]);
  });
  std::vector<std::array<int, 2>> out;
  for (const auto& f : found) out.insert(out.end(), f.begin(), f.end());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace sdm
