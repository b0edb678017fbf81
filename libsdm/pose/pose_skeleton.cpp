#include "libsdm/pose/pose_skeleton.h"

#include "libstm/core/errors.h"
#include "libstm/geometry/differential_geometry.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <string>

namespace sdm {
namespace {

void check_same_graph(const Skeleton& rest, const PosedSkeleton& posed) {
  if (posed.nodes.size() != rest.nodes.size() || posed.edges.size() != rest.edges.size())
    throw InputError("the skeleton has " + std::to_string(posed.nodes.size()) + " nodes and " + std::to_string(posed.edges.size()) +
                     " edges, the SDM's has " + std::to_string(rest.nodes.size()) + " and " + std::to_string(rest.edges.size()) +
                     ": decode needs the same graph with moved nodes");
  for (size_t e = 0; e < rest.edges.size(); ++e) {
    auto a = std::minmax(rest.edges[e][0], rest.edges[e][1]);
    auto b = std::minmax(posed.edges[e][0], posed.edges[e][1]);
    if (a != b)
      throw InputError("skeleton edge " + std::to_string(e) + " joins other nodes than in the SDM: decode needs the same graph");
  }
  if (!posed.node_rotations.empty() && posed.node_rotations.size() != posed.nodes.size())
    throw InputError("the skeleton has " + std::to_string(posed.node_rotations.size()) + " node rotations for " +
                     std::to_string(posed.nodes.size()) + " nodes");
  if (!posed.segment_radius_scale.empty() && posed.segment_radius_scale.size() != posed.edges.size())
    throw InputError("the skeleton has " + std::to_string(posed.segment_radius_scale.size()) + " radius scales for " +
                     std::to_string(posed.edges.size()) + " edges");
}

// The Kabsch fit of offsets `from` onto `to` when they do not lie on one line and it matches each
// within 1e-3 of its length; nothing otherwise.
std::optional<Eigen::Quaterniond> rigid_fit(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to) {
  if (from.size() < 2) return std::nullopt;
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < from.size(); ++i) M += to[i] * from[i].transpose();
  double trace = 0, second = 0;
  const Eigen::Matrix3d R = nearest_rotation(M, &trace, &second);
  if (!(second > 1e-4 * std::abs(trace))) return std::nullopt;  // on a line: the twist about it is free
  for (size_t i = 0; i < from.size(); ++i)
    if ((R * from[i] - to[i]).norm() > 1e-3 * from[i].norm()) return std::nullopt;
  return Eigen::Quaterniond(R).normalized();
}

std::vector<std::vector<int>> children_of(const std::vector<int>& parent) {
  std::vector<std::vector<int>> children(parent.size());
  for (size_t n = 0; n < parent.size(); ++n)
    if (parent[n] >= 0) children[size_t(parent[n])].push_back(int(n));
  return children;
}

std::vector<int> subtree_of(const std::vector<std::vector<int>>& children, int node) {
  std::vector<int> out{node};
  for (size_t i = 0; i < out.size(); ++i)
    for (int c : children[size_t(out[i])]) out.push_back(c);
  return out;
}

// The bone tree by breadth-first search from each component's root: parent node and the edge to it.
void build_tree(const Skeleton& s, std::vector<int>& parent, std::vector<int>& parent_edge, std::vector<int>& order) {
  const size_t n = s.nodes.size();
  std::vector<std::vector<std::pair<int, int>>> adj(n);  // (neighbour, edge)
  for (size_t e = 0; e < s.edges.size(); ++e) {
    adj[size_t(s.edges[e][0])].push_back({s.edges[e][1], int(e)});
    adj[size_t(s.edges[e][1])].push_back({s.edges[e][0], int(e)});
  }
  parent.assign(n, -1);
  parent_edge.assign(n, -1);
  std::vector<char> seen(n, 0);
  order.clear();
  while (order.size() < n) {
    const int root = skeleton_root(s, seen);
    std::deque<int> queue{root};
    seen[size_t(root)] = 1;
    while (!queue.empty()) {
      const int u = queue.front();
      queue.pop_front();
      order.push_back(u);
      for (const auto& [v, e] : adj[size_t(u)])
        if (!seen[size_t(v)]) seen[size_t(v)] = 1, parent[size_t(v)] = u, parent_edge[size_t(v)] = e, queue.push_back(v);
    }
  }
}

}  // namespace

Eigen::Vector3d Bone::stretched(const Eigen::Vector3d& x, const Eigen::Vector3d& p) const {
  if (stretch == 1) return x;
  const double along = std::clamp((x - p).dot(direction), 0.0, length);
  return x + (stretch - 1) * along * direction;
}

bool SkeletonPose::identity() const {
  for (const Bone& b : bones)
    if (b.stretch != 1 || b.radius_scale != 1 || !b.motion.rotation.coeffs().isApprox(Eigen::Quaterniond::Identity().coeffs(), 0) ||
        b.motion.translation != Eigen::Vector3d::Zero())
      return false;
  return true;
}

Eigen::Quaterniond minimal_swing(const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  const double c = from.dot(to);
  if (c < -1 + 1e-12) {
    // Opposite: a half turn about any perpendicular.
    Eigen::Vector3d axis = from.cross(Eigen::Vector3d::UnitX());
    if (axis.norm() < 1e-6) axis = from.cross(Eigen::Vector3d::UnitY());
    return Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, axis.normalized()));
  }
  return Eigen::Quaterniond::FromTwoVectors(from, to).normalized();
}

int skeleton_root(const Skeleton& s, const std::vector<char>& taken) {
  const std::vector<int> degree = s.degrees();
  // The component of the first node not taken, and whether it has a junction.
  std::vector<char> in(s.nodes.size(), 0);
  {
    const auto adj = s.adjacency();
    int first = 0;
    while (size_t(first) < s.nodes.size() && !taken.empty() && taken[size_t(first)]) ++first;
    if (size_t(first) == s.nodes.size()) return -1;
    std::vector<int> stack{first};
    in[size_t(first)] = 1;
    while (!stack.empty()) {
      const int u = stack.back();
      stack.pop_back();
      for (int v : adj[size_t(u)])
        if (!in[size_t(v)]) in[size_t(v)] = 1, stack.push_back(v);
    }
  }
  bool junction = false, end = false;
  for (size_t n = 0; n < s.nodes.size(); ++n)
    if (in[n]) junction |= degree[n] >= 3, end |= degree[n] == 1;
  const bool chain = !junction && end;
  std::vector<int> owned(s.nodes.size(), 0);
  for (int n : s.vertex_node)
    if (n >= 0 && size_t(n) < owned.size()) ++owned[size_t(n)];
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : s.nodes) centroid += p;
  centroid /= double(std::max<size_t>(1, s.nodes.size()));  // (of all components: a tie-break only)
  int best = -1;
  for (size_t n = 0; n < s.nodes.size(); ++n) {
    if (!in[n] || (chain && degree[n] != 1)) continue;
    if (best < 0) {
      best = int(n);
      continue;
    }
    const size_t b = size_t(best);
    if (degree[n] != degree[b]) {
      if (degree[n] > degree[b]) best = int(n);
    } else if (owned[n] != owned[b]) {
      if (owned[n] > owned[b]) best = int(n);
    } else if ((s.nodes[n] - centroid).squaredNorm() < (s.nodes[b] - centroid).squaredNorm()) {
      best = int(n);
    }
  }
  return best;
}

SkeletonPose pose_skeleton(const Skeleton& rest, const PosedSkeleton& posed) {
  check_same_graph(rest, posed);
  const size_t n = rest.nodes.size();
  SkeletonPose pose;
  pose.rest = rest.nodes;
  pose.posed = posed.nodes;
  std::vector<int> parent_edge, order;
  build_tree(rest, pose.node_parent, parent_edge, order);
  std::vector<int> rank(n);
  for (size_t i = 0; i < order.size(); ++i) rank[size_t(order[i])] = int(i);
  // Every edge's head is its end reached first (the parent for tree edges).
  pose.bones.resize(rest.edges.size());
  std::vector<std::vector<int>> out_edges(n);
  for (size_t e = 0; e < rest.edges.size(); ++e) {
    int a = rest.edges[e][0], b = rest.edges[e][1];
    if (rank[size_t(a)] > rank[size_t(b)]) std::swap(a, b);
    Bone& bone = pose.bones[e];
    bone.head = a, bone.tail = b;
    bone.length = (rest.nodes[size_t(b)] - rest.nodes[size_t(a)]).norm();
    bone.direction = (rest.nodes[size_t(b)] - rest.nodes[size_t(a)]) / bone.length;
    bone.stretch = (posed.nodes[size_t(b)] - posed.nodes[size_t(a)]).norm() / bone.length;
    if (!posed.segment_radius_scale.empty()) bone.radius_scale = posed.segment_radius_scale[e];
    out_edges[size_t(a)].push_back(int(e));
  }
  pose.node_rotation.assign(n, Eigen::Quaterniond::Identity());
  const std::vector<std::vector<int>> children = children_of(pose.node_parent);
  for (int u : order) {
    Eigen::Quaterniond R = Eigen::Quaterniond::Identity();
    std::optional<Eigen::Quaterniond> given;
    if (!posed.node_rotations.empty()) given = posed.node_rotations[size_t(u)];
    if (given) {
      R = *given;
    } else {
      // The sub-tree below u turned rigidly about u: its rotation; else its children did.
      std::vector<Eigen::Vector3d> from, to, child_from, child_to;
      for (int v : subtree_of(children, u))
        if (v != u) {
          from.push_back(rest.nodes[size_t(v)] - rest.nodes[size_t(u)]);
          to.push_back(posed.nodes[size_t(v)] - posed.nodes[size_t(u)]);
          if (pose.node_parent[size_t(v)] == u) child_from.push_back(from.back()), child_to.push_back(to.back());
        }
      std::optional<Eigen::Quaterniond> fit = rigid_fit(from, to);
      if (!fit) fit = rigid_fit(child_from, child_to);
      if (fit)
        R = *fit;
      else if (pose.node_parent[size_t(u)] >= 0)
        R = pose.bones[size_t(parent_edge[size_t(u)])].motion.rotation;  // carried on from the bone above
    }
    pose.node_rotation[size_t(u)] = R;
    for (int e : out_edges[size_t(u)]) {
      Bone& b = pose.bones[size_t(e)];
      const Eigen::Vector3d to = (posed.nodes[size_t(b.tail)] - posed.nodes[size_t(u)]).normalized();
      const Eigen::Quaterniond B = (minimal_swing((R * b.direction).normalized(), to) * R).normalized();
      b.motion.rotation = B;
      b.motion.translation = posed.nodes[size_t(u)] - B * rest.nodes[size_t(u)];
    }
  }
  return pose;
}

}  // namespace sdm

namespace sdm {

std::vector<int> subtree_nodes(const SkeletonPose& pose, int node) { return subtree_of(children_of(pose.node_parent), node); }

void rotate_subtree(const Skeleton& rest, PosedSkeleton& posed, int node, const Eigen::Quaterniond& q) {
  if (node < 0 || size_t(node) >= rest.nodes.size())
    throw InputError("node " + std::to_string(node) + " is out of range (the skeleton has " + std::to_string(rest.nodes.size()) + " nodes)");
  const SkeletonPose pose = pose_skeleton(rest, posed);
  posed.node_rotations.assign(pose.node_rotation.begin(), pose.node_rotation.end());
  const Eigen::Vector3d pivot = posed.nodes[size_t(node)];
  for (int n : subtree_nodes(pose, node)) {
    posed.nodes[size_t(n)] = pivot + q * (posed.nodes[size_t(n)] - pivot);
    posed.node_rotations[size_t(n)] = (q * pose.node_rotation[size_t(n)]).normalized();
  }
}

}  // namespace sdm
