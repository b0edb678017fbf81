#include "libsdm/pose/pose_weights.h"

#include "libstm/core/parallel.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <stdexcept>

namespace sdm {
namespace {

// Per node, the segments within `reach` along the skeleton and the distance to their nearest end
// (0 for the segments at the node): a Dijkstra over the rest skeleton, stopped at `reach`.
std::vector<std::vector<std::pair<int, double>>> segments_within(const Layout& layout, double reach) {
  const Skeleton& s = layout.skeleton;
  const size_t n = s.nodes.size();
  std::vector<std::vector<std::pair<int, int>>> adj(n);  // (neighbour, segment)
  for (size_t k = 0; k < layout.segments.size(); ++k) {
    const LayoutSegment& seg = layout.segments[k];
    adj[size_t(seg.a)].push_back({seg.b, int(k)});
    adj[size_t(seg.b)].push_back({seg.a, int(k)});
  }
  std::vector<std::vector<std::pair<int, double>>> out(n);
  std::vector<double> dist(n, INFINITY);
  std::vector<int> touched;
  std::vector<double> seg_dist(layout.segments.size(), INFINITY);
  for (size_t from = 0; from < n; ++from) {
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    dist[from] = 0;
    touched = {int(from)};
    queue.push({0.0, int(from)});
    std::vector<int> segs;
    while (!queue.empty()) {
      const auto [d, u] = queue.top();
      queue.pop();
      if (d > dist[size_t(u)]) continue;
      for (const auto& [v, k] : adj[size_t(u)]) {
        if (seg_dist[size_t(k)] == INFINITY) segs.push_back(k);
        seg_dist[size_t(k)] = std::min(seg_dist[size_t(k)], d);
        const double dv = d + (s.nodes[size_t(v)] - s.nodes[size_t(u)]).norm();
        if (dv < reach && dv < dist[size_t(v)]) {
          if (dist[size_t(v)] == INFINITY) touched.push_back(v);
          dist[size_t(v)] = dv;
          queue.push({dv, v});
        }
      }
    }
    for (int k : segs) out[from].push_back({k, seg_dist[size_t(k)]}), seg_dist[size_t(k)] = INFINITY;
    for (int t : touched) dist[size_t(t)] = INFINITY;
  }
  return out;
}

double kernel(double t) { return t >= 1 ? 0.0 : (1 - t * t) * (1 - t * t); }

// The distance from x to segment s's axis (clamped to the segment) in its radii; `t`: the
// clamped parameter along it from node a.
double radii_from(const Layout& layout, int s, const Eigen::Vector3d& x, double* t = nullptr) {
  const LayoutSegment& seg = layout.segments[size_t(s)];
  const Eigen::Vector3d& a = layout.skeleton.nodes[size_t(seg.a)];
  const Eigen::Vector3d& b = layout.skeleton.nodes[size_t(seg.b)];
  const double length = (b - a).norm();
  const double along = std::clamp((x - a).dot(b - a) / length, 0.0, length);
  if (t) *t = along;
  return (x - (a + along / length * (b - a))).norm() / seg.radius;
}

// The segment a point moves with: its own, unless it lies farther than kPoseStrayRadii from it and
// another lies nearer in radii.
int own_segment(const Layout& layout, int s, const Eigen::Vector3d& x) {
  double best = radii_from(layout, s, x);
  if (best <= kPoseStrayRadii) return s;
  int own = s;
  for (int k = 0; k < int(layout.segments.size()); ++k) {
    const double r = radii_from(layout, k, x);
    if (r < best) best = r, own = k;
  }
  return own;
}

}  // namespace

PoseWeights pose_weights(const Layout& layout, const std::vector<Eigen::Vector3d>& points, const std::vector<int>& point_segment,
                         double blend_radii) {
  if (points.size() != point_segment.size()) throw std::invalid_argument("pose_weights: one segment per point expected");
  const int segments = int(layout.segments.size());
  for (int s : point_segment)
    if (s < 0 || s >= segments) throw std::invalid_argument("pose_weights: segment out of range");
  double largest = 0;
  for (const auto& seg : layout.segments) largest = std::max(largest, seg.radius);
  const auto near = segments_within(layout, blend_radii * largest);
  const size_t n = points.size();
  PoseWeights w;
  w.location.resize(n);
  w.own.resize(n);
  std::vector<std::vector<std::pair<int, double>>> entries(n);
  parallel_for(int(n), 4096, [&](int i) {
    const int s = own_segment(layout, point_segment[size_t(i)], points[size_t(i)]);
    w.own[size_t(i)] = s;
    const LayoutSegment& seg = layout.segments[size_t(s)];
    const Eigen::Vector3d& a = layout.skeleton.nodes[size_t(seg.a)];
    const Eigen::Vector3d& b = layout.skeleton.nodes[size_t(seg.b)];
    const double length = (b - a).norm();
    double t = 0;
    radii_from(layout, s, points[size_t(i)], &t);
    w.location[size_t(i)] = a + t / length * (b - a);
    auto& e = entries[size_t(i)];
    const Eigen::Vector3d& x = points[size_t(i)];
    // Past an end that joins other segments (the face assignment gives a segment the surface a
    // little beyond its nodes, extend_a/b), the point's own weight fades as theirs would.
    const double along = (x - a).dot(b - a) / length;
    double past = 0;
    if (along < 0 && !seg.neighbours_a.empty()) past = -along;
    if (along > length && !seg.neighbours_b.empty()) past = along - length;
    e.push_back({s, kernel(past / (blend_radii * seg.radius))});
    auto visit = [&](int node, double offset) {
      for (const auto& [k, d] : near[size_t(node)]) {
        if (k == s) continue;
        const LayoutSegment& other = layout.segments[size_t(k)];
        const double h = blend_radii * std::min(seg.radius, other.radius);
        double dk = offset + d;
        if (d == 0 && (other.a == node || other.b == node)) {
          // A segment at this node, with the point radially near its axis: the distance by which
          // the point falls short of it along its axis (0 when it projects onto it), so that points
          // of either segment at one place weigh alike.
          const Eigen::Vector3d& p = layout.skeleton.nodes[size_t(node)];
          const Eigen::Vector3d dir = (layout.skeleton.nodes[size_t(other.a == node ? other.b : other.a)] - p).normalized();
          const double tk = (x - p).dot(dir);
          if ((x - p - tk * dir).norm() <= 1.5 * other.radius) dk = std::max(0.0, -tk);
        }
        const double wk = kernel(dk / h);
        if (wk <= 0) continue;
        auto it = std::find_if(e.begin(), e.end(), [k = k](const auto& y) { return y.first == k; });
        if (it == e.end()) e.push_back({k, wk});
        else it->second = std::max(it->second, wk);  // the shorter way round
      }
    };
    visit(seg.a, t);
    visit(seg.b, length - t);
  });
  w.start.resize(n + 1, 0);
  for (size_t i = 0; i < n; ++i) {
    double sum = 0;
    for (const auto& [k, x] : entries[i]) sum += x;
    for (const auto& [k, x] : entries[i]) w.segment.push_back(k), w.weight.push_back(x / sum);
    w.start[i + 1] = int(w.segment.size());
  }
  return w;
}

RigWeights rig_weights(const SkeletonPose& pose, const PoseWeights& weights) {
  RigWeights r;
  r.node_parent = pose.node_parent;
  const size_t n = weights.start.empty() ? 0 : weights.start.size() - 1;
  r.joints.resize(n);
  r.weights.resize(n);
  std::vector<std::pair<double, int>> per_node;
  for (size_t i = 0; i < n; ++i) {
    per_node.clear();
    for (int e = weights.start[i]; e < weights.start[i + 1]; ++e) {
      const int head = pose.bones[size_t(weights.segment[size_t(e)])].head;
      auto it = std::find_if(per_node.begin(), per_node.end(), [head](const auto& x) { return x.second == head; });
      if (it == per_node.end()) per_node.push_back({weights.weight[size_t(e)], head});
      else it->first += weights.weight[size_t(e)];
    }
    std::sort(per_node.begin(), per_node.end(), [](const auto& x, const auto& y) { return x.first > y.first || (x.first == y.first && x.second < y.second); });
    per_node.resize(std::min<size_t>(4, per_node.size()));
    double sum = 0;
    for (const auto& x : per_node) sum += x.first;
    r.joints[i] = {0, 0, 0, 0};
    r.weights[i] = {0, 0, 0, 0};
    for (size_t k = 0; k < per_node.size(); ++k) r.joints[i][k] = per_node[k].second, r.weights[i][k] = float(per_node[k].first / sum);
  }
  return r;
}

}  // namespace sdm
