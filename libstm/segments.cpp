#include "libstm/segments.h"

#include "libstm/errors.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace stm {

double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double* t) {
  const Eigen::Vector3d ab = b - a;
  const double l2 = ab.squaredNorm();
  const double tt = l2 > 0 ? (p - a).dot(ab) / l2 : 0.0;
  if (t) *t = tt;
  const double c = std::clamp(tt, 0.0, 1.0);
  return (p - (a + c * ab)).norm();
}

namespace {

void check_inputs(const Mesh& mesh, const Skeleton& sk) {
  if (sk.edges.empty()) throw InputError("the skeleton has no edge, so there is no segment to map the surface to");
  if (sk.vertex_node.size() != mesh.n_vertices())
    throw InputError("the skeleton maps " + std::to_string(sk.vertex_node.size()) + " vertices but the mesh has " +
                     std::to_string(mesh.n_vertices()) + " (skeleton of another mesh?)");
  for (int n : sk.vertex_node)
    if (n < 0 || n >= int(sk.nodes.size())) throw InputError("the skeleton maps a vertex to node " + std::to_string(n));
}

}  // namespace

std::vector<int> assign_faces(const Mesh& mesh, const Skeleton& sk) {
  check_inputs(mesh, sk);
  std::vector<std::vector<int>> node_edges(sk.nodes.size());
  for (size_t e = 0; e < sk.edges.size(); ++e) {
    node_edges[sk.edges[e][0]].push_back(int(e));
    if (sk.edges[e][1] != sk.edges[e][0]) node_edges[sk.edges[e][1]].push_back(int(e));
  }
  std::vector<int> result(mesh.n_faces(), -1);
  std::vector<int> cand;
  for (auto f : mesh.faces()) {
    Eigen::Vector3d p[3];
    int k = 0;
    cand.clear();
    for (auto v : mesh.fv_range(f)) {
      p[k++] = point(mesh, v);
      for (int e : node_edges[sk.vertex_node[v.idx()]]) cand.push_back(e);
    }
    std::sort(cand.begin(), cand.end());
    cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
    const bool global = cand.empty();  // nodes without edges: any segment may take the face
    if (global)
      for (size_t e = 0; e < sk.edges.size(); ++e) cand.push_back(int(e));
    const Eigen::Vector3d c = (p[0] + p[1] + p[2]) / 3.0;
    Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
    const double nn = n.norm();
    if (nn > 0) n /= nn;
    // Exact ties (a face over a node shared by several segments) are common in symmetric
    // tessellations, so each criterion compares with a tolerance and hands ties to the next one;
    // float noise (a rotated copy of the mesh) then cannot flip the choice.
    int best_over = -1, best_near = -1;
    double over_cos = 0, over_dist = 0, near_dist = 0, near_cos = 0, near_corners = 0;
    const double tol = 1e-9;
    for (int e : cand) {
      const Eigen::Vector3d& a = sk.nodes[sk.edges[e][0]];
      const Eigen::Vector3d& b = sk.nodes[sk.edges[e][1]];
      double t = 0;
      const double dist = distance_to_segment(c, a, b, &t);
      const double len = (b - a).norm();
      const double cs = len > 0 && nn > 0 ? std::abs(n.dot(b - a)) / len : 1.0;
      const double dtol = tol * (dist + len);
      // Last tie-breaker: how far the corners are from the segment (a face centred on a node's
      // plane still leans to one side with its corners).
      const double corners = distance_to_segment(p[0], a, b) + distance_to_segment(p[1], a, b) + distance_to_segment(p[2], a, b);
      const double ctol = tol * (corners + len);
      if (len > 0 && nn > 0 && t >= -tol && t <= 1 + tol) {
        if (best_over < 0 || cs < over_cos - tol || (cs <= over_cos + tol && corners < over_dist - ctol))
          best_over = e, over_cos = cs, over_dist = corners;
      }
      if (best_near < 0 || dist < near_dist - dtol ||
          (dist <= near_dist + dtol && (cs < near_cos - tol || (cs <= near_cos + tol && corners < near_corners - ctol))))
        best_near = e, near_dist = dist, near_cos = cs, near_corners = corners;
    }
    result[f.idx()] = best_over >= 0 ? best_over : best_near;
    if (result[f.idx()] < 0) throw InputError("face " + std::to_string(f.idx()) + " has no skeleton segment in reach");
  }
  return result;
}

std::vector<SegmentGeometry> segment_geometry(const Mesh& mesh, const Skeleton& sk, const std::vector<int>& face_segment) {
  check_inputs(mesh, sk);
  if (face_segment.size() != mesh.n_faces()) throw InputError("face_segment does not match the mesh");
  const size_t ns = sk.edges.size();
  std::vector<SegmentGeometry> g(ns);
  std::vector<double> rsum(ns, 0.0);
  for (auto f : mesh.faces()) {
    const int s = face_segment[f.idx()];
    if (s < 0 || s >= int(ns)) throw InputError("face " + std::to_string(f.idx()) + " names no segment");
    const Eigen::Vector3d& a = sk.nodes[sk.edges[s][0]];
    const Eigen::Vector3d& b = sk.nodes[sk.edges[s][1]];
    Eigen::Vector3d p[3];
    int k = 0;
    for (auto v : mesh.fv_range(f)) p[k++] = point(mesh, v);
    const double area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    // The vertices, not the centroid: the centroid of a flat triangle lies inside a curved surface.
    double r = 0;
    for (const auto& q : p) r += distance_to_segment(q, a, b);
    g[s].area += area;
    rsum[s] += area * r / 3.0;
  }
  for (size_t s = 0; s < ns; ++s) {
    g[s].length = (sk.nodes[sk.edges[s][1]] - sk.nodes[sk.edges[s][0]]).norm();
    if (g[s].area > 0) g[s].radius = rsum[s] / g[s].area;
  }
  // Segments without faces borrow the radius of adjacent segments that have some.
  std::vector<std::vector<int>> node_edges(sk.nodes.size());
  for (size_t e = 0; e < ns; ++e) {
    node_edges[sk.edges[e][0]].push_back(int(e));
    node_edges[sk.edges[e][1]].push_back(int(e));
  }
  for (size_t s = 0; s < ns; ++s) {
    if (g[s].area > 0) continue;
    double sum = 0;
    int cnt = 0;
    for (int end : sk.edges[s])
      for (int e : node_edges[end])
        if (g[e].area > 0) sum += g[e].radius, ++cnt;
    g[s].radius = cnt ? sum / cnt : std::max(g[s].length * 0.1, 1e-12);
  }
  for (auto& x : g) x.cap = M_PI * x.radius / 2.0;
  return g;
}

}  // namespace stm
