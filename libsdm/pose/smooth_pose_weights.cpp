#include "libsdm/pose/smooth_pose_weights.h"

#include "libstm/core/parallel.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <queue>
#include <stdexcept>

namespace sdm {
namespace {

// A ball's points are weighed by their straight distance: the kernel of a path length along a
// sheared tessellation varied from vertex to vertex (a capsule's half twist crossed 5060 face
// pairs), the straight distance is smooth. A point is smoothed when a blending point lies within
// kBallReach times the radius along the edges (paths along edges run at most sqrt(2) over the
// straight distance on a well-shaped grid).
constexpr double kBallReach = 1.6;
// Segments this far apart along the skeleton, in radii, may share a smoothed point: the kernel's
// reach and the ball's.
constexpr double kNearRadii = kPoseBlendRadii + kBallReach * kPoseSmoothRadii;

// The surface's edge graph (per point: neighbour, edge length) and each point's area (a third of
// its triangles').
struct SurfaceGraph {
  std::vector<std::vector<std::pair<int, double>>> adj;
  std::vector<double> area;
};

SurfaceGraph surface_graph(const Eigen::MatrixX3i& triangles, const std::vector<Eigen::Vector3d>& points) {
  const int n = int(points.size());
  SurfaceGraph g;
  g.adj.resize(size_t(n));
  g.area.assign(size_t(n), 0.0);
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    for (int c = 0; c < 3; ++c)
      if (triangles(t, c) < 0 || triangles(t, c) >= n) throw std::invalid_argument("smooth_pose_weights: a triangle names a point out of range");
    const Eigen::Vector3d &p0 = points[size_t(triangles(t, 0))], &p1 = points[size_t(triangles(t, 1))], &p2 = points[size_t(triangles(t, 2))];
    const double third = (p1 - p0).cross(p2 - p0).norm() / 6;
    for (int c = 0; c < 3; ++c) {
      const int a = triangles(t, c), b = triangles(t, (c + 1) % 3);
      const double length = (points[size_t(a)] - points[size_t(b)]).norm();
      g.adj[size_t(a)].push_back({b, length});
      g.adj[size_t(b)].push_back({a, length});
      g.area[size_t(a)] += third;
    }
  }
  for (auto& a : g.adj) {
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end(), [](const auto& x, const auto& y) { return x.first == y.first; }), a.end());
  }
  return g;
}

// Two bones move alike when their motions differ by less than a pose can be told apart in single
// precision: a skeleton posed in Blender or read from glTF holds its node positions and rotations in
// float32 (relative rounding 6e-8), so a bone that did not move differs from the identity by about
// 1e-7 of the model's extent. Tolerance 1e-6 in stretch, in turn (radians) and in translation over
// the extent; with exact ties (1e-12) such noise split every bone into its own group and moved
// points near an edited joint by 3e-4 of the diagonal (Spot, a leg turned 45 degrees in Blender).
constexpr double kAlike = 1e-6;

bool alike(const Bone& a, const Bone& b, double extent) {
  if (std::abs(a.radius_scale - b.radius_scale) > kAlike) return false;
  if (std::abs(a.stretch - 1) > kAlike || std::abs(b.stretch - 1) > kAlike) return false;
  return a.motion.rotation.angularDistance(b.motion.rotation) <= kAlike &&
         (a.motion.translation - b.motion.translation).norm() <= kAlike * extent;
}

// Per point, its ball's radius before the spread to its neighbours: the smaller of kPoseSmoothRadii
// of its segment's radius and the largest distance between where its own bone and another of
// its weights' bones take it (0 where its weights fall on one motion group). A jump dw in the
// weights moves the surface by dw times that distance, so a blend of motions that barely differ
// needs little smoothing, and a ball as wide as the shift spreads a jump of 1/2 to a slope of at
// most 1/2. (In a whole-body pose such as 001 posed like 007 the shifts exceed the cap almost
// everywhere: every point is smoothed, balls of about 400 points.)
std::vector<double> ball_radii(const PoseWeights& w, const std::vector<Eigen::Vector3d>& points, const SkeletonPose& pose,
                               const std::vector<int>& group, const Layout& layout) {
  const size_t n = points.size();
  std::vector<double> rho(n, 0.0);
  parallel_for(int(n), 4096, [&](int i) {
    const int own = w.own[size_t(i)];
    const Bone& b = pose.bones[size_t(own)];
    const double r = layout.segments[size_t(own)].radius;
    double shift = 0;
    for (int e = w.start[size_t(i)]; e < w.start[size_t(i) + 1]; ++e) {
      const int k = w.segment[size_t(e)];
      if (group[size_t(k)] == group[size_t(own)]) continue;
      const Bone& o = pose.bones[size_t(k)];
      const Eigen::Vector3d& x = points[size_t(i)];
      double d = (o.motion(x) - b.motion(x)).norm();
      d += std::abs(o.radius_scale - b.radius_scale) * r + std::abs(o.stretch - b.stretch) * std::max(o.length, b.length);
      shift = std::max(shift, d);
    }
    rho[size_t(i)] = std::min(kPoseSmoothRadii * r, shift);
  });
  return rho;
}

// The points to smooth and their balls' radii: every point within kBallReach * rho[i] along the
// edges of a point i with rho[i] > 0 takes the radius of the one that reaches it with the most to
// spare, or its own when larger. Returns the radius per point, 0 where nothing is smoothed.
std::vector<double> points_to_smooth(const SurfaceGraph& g, const std::vector<double>& rho) {
  const size_t n = rho.size();
  std::vector<double> left(n, -1), radius(n, 0.0);  // reach left on arrival, the source's radius
  using Item = std::pair<double, int>;
  std::priority_queue<Item> queue;
  for (size_t i = 0; i < n; ++i)
    if (rho[i] > 0) left[i] = kBallReach * rho[i], radius[i] = rho[i], queue.push({left[i], int(i)});
  while (!queue.empty()) {
    const auto [r, u] = queue.top();
    queue.pop();
    if (r < left[size_t(u)]) continue;
    for (const auto& [v, length] : g.adj[size_t(u)])
      if (r - length > left[size_t(v)]) left[size_t(v)] = r - length, radius[size_t(v)] = radius[size_t(u)], queue.push({r - length, v});
  }
  for (size_t i = 0; i < n; ++i) radius[i] = std::max(radius[i], rho[i]);
  return radius;
}

double kernel(double t) { return t >= 1 ? 0.0 : (1 - t * t) * (1 - t * t); }

// The points of i's ball: those within rho of it (straight) that the edges reach from it without
// leaving that distance, so that the ball stays on this side of a contact (fingers side by side).
// `seen` (all 0 on entry and on return) and `touched` are the caller's scratch space.
void ball_points(const SurfaceGraph& g, const std::vector<Eigen::Vector3d>& points, int i, double rho, std::vector<char>& seen,
                 std::vector<int>& touched) {
  const double rho2 = rho * rho;
  touched = {i};
  seen[size_t(i)] = 1;
  for (size_t next = 0; next < touched.size(); ++next)
    for (const auto& [v, length] : g.adj[size_t(touched[next])])
      if (!seen[size_t(v)] && (points[size_t(v)] - points[size_t(i)]).squaredNorm() < rho2) seen[size_t(v)] = 1, touched.push_back(v);
  for (int t : touched) seen[size_t(t)] = 0;
}

// Point i's group weights smoothed over its ball of radius rho, over `groups` only (near_groups of
// its own segment) and from the ball's points owned by them: (group, weight) pairs. Each group's
// weight is fitted by a linear function of position, weighed by the kernel of the straight distance
// times the point's area (moving least squares of degree 1): a fit reproduces a weight that varies
// linearly, where a plain average of the ball (degree 0) is off by the gradient times the offset
// of the ball's centroid, which moves from vertex to vertex (0.005 between neighbours across a
// capsule's half twist, which turned sliver triangles over: 12 face pairs crossed).
std::vector<std::pair<int, double>> ball_fit(const SurfaceGraph& g, const std::vector<Eigen::Vector3d>& points, const PoseWeights& w,
                                             const std::vector<int>& group, const std::vector<int>& groups, int i, double rho,
                                             std::vector<char>& seen, std::vector<int>& touched) {
  ball_points(g, points, i, rho, seen, touched);
  Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(4, Eigen::Index(groups.size()));
  for (int u : touched) {
    if (std::find(groups.begin(), groups.end(), group[size_t(w.own[size_t(u)])]) == groups.end()) continue;
    const Eigen::Vector3d d = (points[size_t(u)] - points[size_t(i)]) / rho;
    const double k = kernel(d.norm()) * g.area[size_t(u)];
    if (k <= 0) continue;
    const Eigen::Vector4d basis(1, d.x(), d.y(), d.z());
    normal += k * basis * basis.transpose();
    for (int e = w.start[size_t(u)]; e < w.start[size_t(u) + 1]; ++e) {
      const auto at = std::find(groups.begin(), groups.end(), group[size_t(w.segment[size_t(e)])]) - groups.begin();
      if (at < Eigen::Index(groups.size())) rhs.col(at) += k * w.weight[size_t(e)] * basis;
    }
  }
  // A small ridge on the gradient: the ball is nearly flat, so the gradient along the normal is
  // barely determined.
  normal.diagonal().tail<3>().array() += 1e-2 * normal(0, 0);
  const Eigen::MatrixXd fit = normal.ldlt().solve(rhs);
  std::vector<std::pair<int, double>> out;
  double kept = 0;
  for (size_t c = 0; c < groups.size(); ++c)
    if (fit(0, Eigen::Index(c)) >= kPoseWeightFloor) out.push_back({groups[c], fit(0, Eigen::Index(c))}), kept += out.back().second;
  if (!(kept > 0)) {  // nothing fitted (a degenerate ball): the point keeps its own weights
    out.clear();
    for (int e = w.start[size_t(i)]; e < w.start[size_t(i) + 1]; ++e) out.push_back({w.segment[size_t(e)], w.weight[size_t(e)]});
    return out;
  }
  for (auto& x : out) x.second /= kept;
  return out;
}

// Per segment, the motion groups a point of it may take from its ball: those of the segments
// within kNearRadii of the larger radius of the two along the skeleton (from an end of one to an end
// of the other). Surface that meets where the skeleton keeps parts apart (two feet side by side)
// is contact, not a joint: averaged across it, 007 posed like 001 moved points of a leg by a third
// of the other leg's motion, 24 % of the diagonal. The segments whose kernel weights meet are not
// enough either: at FAUST's arm pivot the points of a segment touch those of one two segments away
// along the chain, past a segment shorter than the blend reach, and without smoothing there the
// twist crossed 110 face pairs.
std::vector<std::vector<int>> near_groups(const Layout& layout, const std::vector<int>& group) {
  const Skeleton& sk = layout.skeleton;
  const size_t segments = layout.segments.size();
  double largest = 0;
  for (const auto& seg : layout.segments) largest = std::max(largest, seg.radius);
  std::vector<std::vector<std::pair<int, int>>> adj(sk.nodes.size());  // (neighbour, segment)
  for (size_t k = 0; k < segments; ++k) {
    adj[size_t(layout.segments[k].a)].push_back({layout.segments[k].b, int(k)});
    adj[size_t(layout.segments[k].b)].push_back({layout.segments[k].a, int(k)});
  }
  std::vector<std::vector<int>> near(segments);
  std::vector<double> dist(sk.nodes.size(), INFINITY);
  for (size_t s = 0; s < segments; ++s) {
    const double reach = kNearRadii * largest;
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    std::vector<int> touched{layout.segments[s].a, layout.segments[s].b};
    for (int e : touched) dist[size_t(e)] = 0, queue.push({0.0, e});
    near[s] = {group[s]};
    while (!queue.empty()) {
      const auto [d, u] = queue.top();
      queue.pop();
      if (d > dist[size_t(u)]) continue;
      for (const auto& [v, k] : adj[size_t(u)]) {
        const double limit = kNearRadii * std::max(layout.segments[s].radius, layout.segments[size_t(k)].radius);
        if (d <= limit && std::find(near[s].begin(), near[s].end(), group[size_t(k)]) == near[s].end()) near[s].push_back(group[size_t(k)]);
        const double dv = d + (sk.nodes[size_t(v)] - sk.nodes[size_t(u)]).norm();
        if (dv <= reach && dv < dist[size_t(v)]) {
          if (dist[size_t(v)] == INFINITY) touched.push_back(v);
          dist[size_t(v)] = dv;
          queue.push({dv, v});
        }
      }
    }
    for (int t : touched) dist[size_t(t)] = INFINITY;
  }
  return near;
}

}  // namespace

std::vector<int> motion_groups(const SkeletonPose& pose) {
  double extent = 0;
  for (const auto& p : pose.rest) extent = std::max(extent, (p - pose.rest.front()).norm());
  std::vector<int> group(pose.bones.size());
  for (size_t k = 0; k < pose.bones.size(); ++k) {
    group[k] = int(k);
    for (size_t j = 0; j < k; ++j)
      if (group[j] == int(j) && alike(pose.bones[j], pose.bones[k], extent)) {
        group[k] = int(j);
        break;
      }
  }
  return group;
}

namespace {

// The smoothing itself: `group` per segment, `rho` per point (0: not a source; see ball_radii).
void smooth_weights(PoseWeights& w, const std::vector<Eigen::Vector3d>& points, const Eigen::MatrixX3i& triangles,
                    const std::vector<int>& group, const std::vector<double>& rho, const Layout& layout) {
  const size_t n = points.size();
  const SurfaceGraph g = surface_graph(triangles, points);
  const std::vector<double> radius = points_to_smooth(g, rho);
  std::vector<int> todo;
  for (size_t i = 0; i < n; ++i)
    if (radius[i] > 0) todo.push_back(int(i));
  if (todo.empty()) return;
  const std::vector<std::vector<int>> near = near_groups(layout, group);
  std::vector<std::vector<std::pair<int, double>>> smoothed(todo.size());
  const int chunk = 256;
  parallel_for(int((todo.size() + chunk - 1) / chunk), 1, [&](int c) {
    std::vector<char> seen(n, 0);
    std::vector<int> touched;
    for (size_t k = size_t(c) * chunk; k < std::min(todo.size(), size_t(c + 1) * chunk); ++k)
      smoothed[k] = ball_fit(g, points, w, group, near[size_t(w.own[size_t(todo[k])])], todo[k], radius[size_t(todo[k])], seen, touched);
  });
  PoseWeights out;
  out.location = std::move(w.location);
  out.own = std::move(w.own);
  out.start.assign(n + 1, 0);
  size_t next = 0;
  for (size_t i = 0; i < n; ++i) {
    if (next < todo.size() && size_t(todo[next]) == i) {
      for (const auto& [gr, x] : smoothed[next]) out.segment.push_back(gr), out.weight.push_back(x);
      ++next;
    } else {
      for (int e = w.start[i]; e < w.start[i + 1]; ++e) out.segment.push_back(w.segment[size_t(e)]), out.weight.push_back(w.weight[size_t(e)]);
    }
    out.start[i + 1] = int(out.segment.size());
  }
  w = std::move(out);
}

void check_sizes(const PoseWeights& w, const std::vector<Eigen::Vector3d>& points, size_t segments, const Layout& layout) {
  const size_t n = points.size();
  if (w.own.size() != n || w.start.size() != n + 1 || layout.segments.size() != segments)
    throw std::invalid_argument("smooth_pose_weights: one weight row per point and one bone per segment expected");
}

}  // namespace

void smooth_pose_weights(PoseWeights& w, const std::vector<Eigen::Vector3d>& points, const Eigen::MatrixX3i& triangles,
                         const SkeletonPose& pose, const Layout& layout) {
  check_sizes(w, points, pose.bones.size(), layout);
  const std::vector<int> group = motion_groups(pose);
  smooth_weights(w, points, triangles, group, ball_radii(w, points, pose, group, layout), layout);
}

void smooth_rig_weights(PoseWeights& w, const std::vector<Eigen::Vector3d>& points, const Eigen::MatrixX3i& triangles,
                        const Layout& layout) {
  check_sizes(w, points, layout.segments.size(), layout);
  std::vector<int> group(layout.segments.size());
  for (size_t k = 0; k < group.size(); ++k) group[k] = int(k);
  std::vector<double> rho(points.size(), 0.0);
  for (size_t i = 0; i < points.size(); ++i)
    if (w.start[i + 1] - w.start[i] > 1) rho[i] = kPoseSmoothRadii * layout.segments[size_t(w.own[i])].radius;
  smooth_weights(w, points, triangles, group, rho, layout);
}

}  // namespace sdm
