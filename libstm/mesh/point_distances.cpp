#include "libstm/mesh/point_distances.h"

#include "libstm/core/parallel.h"
#include "libstm/geometry/triangle_bvh.h"

namespace sdm {

PointDistances points_to_mesh(const std::vector<Eigen::Vector3d>& points, const Mesh& mesh) {
  const TriangleBvh bvh(vertex_matrix(mesh), face_matrix(mesh));
  std::vector<double> d(points.size(), 0.0);
  parallel_for(int(points.size()), 1024, [&](int i) { d[size_t(i)] = bvh.closest_point(points[size_t(i)]).distance; });
  PointDistances out;
  double sum = 0, sum2 = 0;
  for (size_t i = 0; i < d.size(); ++i) {
    sum += d[i], sum2 += d[i] * d[i];
    if (d[i] > out.max) out.max = d[i], out.worst = points[i];
  }
  if (!d.empty()) out.mean = sum / double(d.size()), out.rms = std::sqrt(sum2 / double(d.size()));
  return out;
}

}  // namespace sdm
