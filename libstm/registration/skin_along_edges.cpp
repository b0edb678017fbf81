#include "libstm/registration/skin_along_edges.h"

#include "libstm/geometry/differential_geometry.h"

#include <algorithm>
#include <cmath>

namespace sdm {

std::vector<EdgeSkin> skin_along_edges(const Skeleton& skeleton, const std::vector<Eigen::Vector3d>& points,
                                       const std::vector<Eigen::Vector3d>& nodes, const std::vector<std::vector<int>>& adjacency) {
  std::vector<EdgeSkin> skin(points.size());
  for (size_t v = 0; v < points.size(); ++v) {
    const int n = skeleton.vertex_node[v];
    EdgeSkin& s = skin[v];
    s.node[0] = s.node[1] = n;
    double best = INFINITY;
    for (int m : adjacency[size_t(n)]) {
      double t = 0;
      const double d = distance_to_segment(points[v], nodes[size_t(n)], nodes[size_t(m)], &t);
      if (d < best) {
        best = d;
        t = std::clamp(t, 0.0, 1.0);
        s.node[1] = m, s.w[0] = 1 - t, s.w[1] = t;
      }
    }
  }
  return skin;
}

}  // namespace sdm
