#include "libstm/render/splat_mesh.h"

#include "libstm/core/errors.h"
#include "libstm/core/parallel.h"
#include "libstm/geometry/point_kdtree.h"
#include "libstm/mesh/add_faces.h"

#include <array>
#include <cmath>

namespace sdm {

namespace {
constexpr int kSides = 6;
constexpr int kSpacingRank = 6;  // the neighbour whose distance sets a disk's radius
}  // namespace

Splats splat_mesh(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                  const std::vector<Eigen::Vector3f>& colors, double scale) {
  const size_t n = points.size();
  if (normals.size() != n || (!colors.empty() && colors.size() != n))
    throw InputError("splat_mesh: " + std::to_string(n) + " points with " + std::to_string(normals.size()) + " normals and " +
                     std::to_string(colors.size()) + " colours");
  // Each disk's centre and rim, computed in parallel, then added to the mesh in order.
  std::vector<std::array<Eigen::Vector3d, kSides + 1>> disks(n);
  const PointKdTree tree(points);
  parallel_for(int(n), 1024, [&](int i) {
    int index[kSpacingRank + 1];
    double d2[kSpacingRank + 1];
    const int m = tree.nearest(points[size_t(i)], kSpacingRank + 1, index, d2);
    const double r = scale * std::sqrt(m == 0 ? 0.0 : d2[m - 1]);
    const Eigen::Vector3d& nrm = normals[size_t(i)];
    const Eigen::Vector3d u = nrm.unitOrthogonal(), v = nrm.cross(u);
    auto& disk = disks[size_t(i)];
    disk[0] = points[size_t(i)];
    for (int k = 0; k < kSides; ++k) {
      const double a = 2 * M_PI * k / kSides;
      disk[size_t(k + 1)] = points[size_t(i)] + r * (std::cos(a) * u + std::sin(a) * v);
    }
  });
  Splats s;
  s.mesh.reserve(n * (kSides + 1), n * 2 * kSides, n * kSides);
  std::vector<std::array<int, 3>> triangles;
  triangles.reserve(n * kSides);
  for (size_t i = 0; i < n; ++i) {
    const int c = int(s.mesh.n_vertices());
    for (const Eigen::Vector3d& p : disks[i]) s.mesh.add_vertex(Mesh::Point(p.x(), p.y(), p.z()));
    for (int k = 0; k < kSides; ++k) triangles.push_back({c, c + 1 + k, c + 1 + (k + 1) % kSides});
    if (!colors.empty()) s.colors.insert(s.colors.end(), kSides + 1, colors[i]);
  }
  add_faces_or_each(s.mesh, triangles);
  return s;
}

}  // namespace sdm
