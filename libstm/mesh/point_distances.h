#pragma once
/// How far points lie from a surface: one-sided distances from every point to the nearest point of a
/// mesh's triangles (exact closest points), e.g. a scan's points to the surface decoded from its map.
#include "libstm/mesh/mesh.h"

#include <vector>

namespace sdm {

struct PointDistances {
  double rms = 0, mean = 0, max = 0;
  Eigen::Vector3d worst = Eigen::Vector3d::Zero();  ///< the point farthest from the surface
};

PointDistances points_to_mesh(const std::vector<Eigen::Vector3d>& points, const Mesh& mesh);

}  // namespace sdm
