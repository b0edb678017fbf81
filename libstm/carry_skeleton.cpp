#include "libstm/carry_skeleton.h"

#include "libstm/errors.h"
#include "libstm/triangle_bvh.h"

#include <algorithm>

namespace stm {

Skeleton carry_skeleton(const Mesh& source, const Skeleton& skeleton, const Mesh& target, const Similarity& T) {
  if (skeleton.vertex_node.size() != source.n_vertices())
    throw InputError("the source skeleton maps " + std::to_string(skeleton.vertex_node.size()) + " vertices, the source has " +
                     std::to_string(source.n_vertices()));
  Skeleton out;
  out.edges = skeleton.edges;
  for (const auto& p : skeleton.nodes) out.nodes.push_back(T(p));
  const Eigen::MatrixX3d V = vertex_matrix(source);
  const Eigen::MatrixX3i F = face_matrix(source);
  const TriangleBvh bvh(V, F);
  const Similarity Ti = T.inverse();
  out.vertex_node.resize(target.n_vertices());
  for (auto v : target.vertices()) {
    const auto c = bvh.closest_point(Ti(point(target, v)));
    int best = F(c.face, 0);
    for (int k = 1; k < 3; ++k)
      if ((V.row(F(c.face, k)).transpose() - c.point).norm() < (V.row(best).transpose() - c.point).norm()) best = F(c.face, k);
    out.vertex_node[v.idx()] = skeleton.vertex_node[best];
  }
  std::vector<int> count(out.nodes.size(), 0);
  for (int x : out.vertex_node) ++count[x];
  for (size_t node = 0; node < out.nodes.size(); ++node) {
    if (count[node] > 0) continue;
    int best = -1;
    double best_d = INFINITY;
    for (auto v : target.vertices())
      if (count[out.vertex_node[v.idx()]] > 1) {
        const double d = (point(target, v) - out.nodes[node]).norm();
        if (d < best_d) best_d = d, best = v.idx();
      }
    if (best < 0) continue;  // fewer vertices than nodes: nothing to give
    --count[out.vertex_node[best]];
    out.vertex_node[best] = int(node);
    ++count[node];
  }
  return out;
}

}  // namespace stm
