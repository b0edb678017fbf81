#include "libstm/registration/carry_skeleton.h"

#include "libstm/core/errors.h"
#include "libstm/geometry/triangle_bvh.h"

#include <algorithm>

namespace sdm {

std::vector<SourcePoint> source_points_under(const Mesh& source, const std::vector<Eigen::Vector3d>& placed,
                                             const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals) {
  const Eigen::MatrixX3i F = face_matrix(source);
  Eigen::MatrixX3d P(placed.size(), 3);
  for (size_t v = 0; v < placed.size(); ++v) P.row(Eigen::Index(v)) = placed[v].transpose();
  const TriangleBvh bvh(P, F);
  std::vector<SourcePoint> out;
  out.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d& q = points[i];
    auto c = bvh.closest_point(q);
    if (normals.size() == points.size() && c.face >= 0) {
      const Eigen::Vector3d a = P.row(F(c.face, 0)), b = P.row(F(c.face, 1)), d = P.row(F(c.face, 2));
      if ((b - a).cross(d - a).dot(normals[i]) < 0) {
        const auto facing = bvh.closest_point_facing(q, normals[i], 0.0);
        if (facing.face >= 0) c = facing;
      }
    }
    out.push_back({c.face, barycentric(c.point, P.row(F(c.face, 0)), P.row(F(c.face, 1)), P.row(F(c.face, 2)))});
  }
  return out;
}

int heaviest_corner(const Mesh& source, const SourcePoint& q) {
  int c = 0, best = 0;
  int corner[3];
  for (auto v : source.fv_range(source.face_handle(q.face))) corner[c++] = v.idx();
  for (int k = 1; k < 3; ++k)
    if (q.barycentric[k] > q.barycentric[best]) best = k;
  return corner[best];
}

Eigen::Vector3d position_of(const Mesh& source, const SourcePoint& q) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  int k = 0;
  for (auto v : source.fv_range(source.face_handle(q.face))) p += q.barycentric[k++] * point(source, v);
  return p;
}

std::vector<int> vertex_nodes_through(const Mesh& source, const Skeleton& skeleton, const std::vector<SourcePoint>& under,
                                      const Mesh& target, const std::vector<Eigen::Vector3d>& nodes) {
  std::vector<int> vertex_node(target.n_vertices(), 0);
  for (size_t j = 0; j < under.size(); ++j) vertex_node[j] = skeleton.vertex_node[size_t(heaviest_corner(source, under[j]))];
  std::vector<int> count(nodes.size(), 0);
  for (int x : vertex_node) ++count[x];
  for (size_t node = 0; node < nodes.size(); ++node) {
    if (count[node] > 0) continue;
    int best = -1;
    double best_d = INFINITY;
    for (auto v : target.vertices())
      if (count[vertex_node[v.idx()]] > 1) {
        const double d = (point(target, v) - nodes[node]).norm();
        if (d < best_d) best_d = d, best = v.idx();
      }
    if (best < 0) continue;  // fewer vertices than nodes: nothing to give
    --count[vertex_node[best]];
    vertex_node[best] = int(node);
    ++count[node];
  }
  return vertex_node;
}

Skeleton carry_skeleton(const Mesh& source, const Skeleton& skeleton, const Mesh& target, const Similarity& T) {
  if (skeleton.vertex_node.size() != source.n_vertices())
    throw InputError("the source skeleton maps " + std::to_string(skeleton.vertex_node.size()) + " vertices, the source has " +
                     std::to_string(source.n_vertices()));
  Skeleton out;
  out.edges = skeleton.edges;
  for (const auto& p : skeleton.nodes) out.nodes.push_back(T(p));
  std::vector<Eigen::Vector3d> placed;
  placed.reserve(source.n_vertices());
  for (auto v : source.vertices()) placed.push_back(T(point(source, v)));
  std::vector<Eigen::Vector3d> points;
  points.reserve(target.n_vertices());
  for (auto v : target.vertices()) points.push_back(point(target, v));
  out.vertex_node = vertex_nodes_through(source, skeleton, source_points_under(source, placed, points), target, out.nodes);
  return out;
}

}  // namespace sdm
