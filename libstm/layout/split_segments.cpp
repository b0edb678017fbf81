#include "libstm/layout/split_segments.h"

#include "libstm/layout/segments.h"

#include <algorithm>
#include <cmath>

namespace sdm {

namespace {
// A new node moves to the centre of its vertices when that lies this many radii off the chord.
constexpr double kBend = 0.05;
}  // namespace

Skeleton split_long_segments(const Mesh& mesh, const Skeleton& sk, double max_ratio, std::vector<int>* origin) {
  // The first pass's faces: their geometry's radii are the ones the layout's rectangles are made for
  // (assign_faces' radii_used), without the second pass's work.
  const std::vector<int> fs = assign_faces(mesh, sk, nullptr, false);  // also checks the inputs
  if (origin) {
    origin->resize(sk.edges.size());
    for (size_t e = 0; e < sk.edges.size(); ++e) (*origin)[e] = int(e);
  }
  if (!(max_ratio > 0) || !std::isfinite(max_ratio)) return sk;
  const std::vector<SegmentGeometry> geo = segment_geometry(mesh, sk, fs);
  const int ne = int(sk.edges.size()), nn = int(sk.nodes.size());
  std::vector<int> pieces(ne, 1);
  for (int e = 0; e < ne; ++e) {
    if (sk.edges[e][0] == sk.edges[e][1] || !(geo[e].radius > 0)) continue;
    const double n = std::ceil(geo[e].length / (max_ratio * geo[e].radius) - 1e-9);
    pieces[e] = int(std::clamp(n, 1.0, 1000.0));
  }
  std::vector<std::vector<int>> node_edges(nn);
  for (int e = 0; e < ne; ++e) {
    node_edges[sk.edges[e][0]].push_back(e);
    if (sk.edges[e][1] != sk.edges[e][0]) node_edges[sk.edges[e][1]].push_back(e);
  }
  // slot[v] = (edge, k): vertex v moves to the k-th inner point of the edge (1 <= k < pieces).
  std::vector<std::pair<int, int>> slot(mesh.n_vertices(), {-1, 0});
  for (auto v : mesh.vertices()) {
    const int x = sk.vertex_node[v.idx()];
    const Eigen::Vector3d p = point(mesh, v);
    int best = -1;
    double best_d = 0, best_t = 0;
    for (int e : node_edges[x]) {
      double t = 0;
      const double d = distance_to_segment(p, sk.nodes[sk.edges[e][0]], sk.nodes[sk.edges[e][1]], &t);
      if (best < 0 || d < best_d * (1 - 1e-12)) best = e, best_d = d, best_t = t;
    }
    if (best < 0 || pieces[best] < 2) continue;
    const int k = int(std::lround(std::clamp(best_t, 0.0, 1.0) * pieces[best]));
    if (k >= 1 && k < pieces[best]) slot[v.idx()] = {best, k};
  }
  // Centres of the vertices of every inner point.
  std::vector<std::vector<Eigen::Vector3d>> sum(ne);
  std::vector<std::vector<int>> count(ne);
  for (int e = 0; e < ne; ++e) sum[e].assign(pieces[e], Eigen::Vector3d::Zero()), count[e].assign(pieces[e], 0);
  for (auto v : mesh.vertices()) {
    const auto [e, k] = slot[v.idx()];
    if (e < 0) continue;
    sum[e][k] += point(mesh, v);
    ++count[e][k];
  }
  Skeleton out = sk;
  std::vector<std::vector<int>> inner(ne);
  for (int e = 0; e < ne; ++e) {
    inner[e].assign(pieces[e], -1);
    std::vector<int> chain{sk.edges[e][0]};
    for (int k = 1; k < pieces[e]; ++k) {
      if (count[e][k] == 0) continue;
      inner[e][k] = int(out.nodes.size());
      // On the chord unless the tube bends away from it: a straight tube keeps its exact axis
      // (a slice's centre wobbles with the tessellation), a curved one gets its nodes on its centre line.
      const Eigen::Vector3d chord = sk.nodes[sk.edges[e][0]] + (sk.nodes[sk.edges[e][1]] - sk.nodes[sk.edges[e][0]]) * (double(k) / pieces[e]);
      const Eigen::Vector3d centre = sum[e][k] / count[e][k];
      out.nodes.push_back((centre - chord).norm() > kBend * geo[e].radius ? centre : chord);
      chain.push_back(inner[e][k]);
    }
    chain.push_back(sk.edges[e][1]);
    out.edges[e] = {chain[0], chain[1]};
    for (size_t i = 1; i + 1 < chain.size(); ++i) {
      out.edges.push_back({chain[i], chain[i + 1]});
      if (origin) origin->push_back(e);
    }
  }
  for (auto v : mesh.vertices()) {
    const auto [e, k] = slot[v.idx()];
    if (e >= 0) out.vertex_node[v.idx()] = inner[e][k];
  }
  return out;
}

}  // namespace sdm
