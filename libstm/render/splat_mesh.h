#pragma once
/// A point cloud as the renderer draws it: one oriented disk per point (a surfel, Pfister et al.
/// 2000), a hexagon in the plane square to the point's normal, wide enough that neighbouring disks
/// overlap and a scan reads as the surface it samples. Lit like any mesh (two-sided headlight), so
/// the normals' orientation does not show, only their direction.
#include "libstm/mesh/mesh.h"

#include <Eigen/Dense>
#include <vector>

namespace sdm {

/// The disks and, when the cloud has colours, the colour of every disk vertex (its point's).
struct Splats {
  Mesh mesh;
  std::vector<Eigen::Vector3f> colors;
};

/// Hexagons (seven vertices, six triangles each) centred on `points`, square to `normals` (one unit
/// vector per point), of radius `scale` times the distance from the point to its sixth nearest
/// neighbour (about the spacing of the points around it, so dense and sparse parts both close up).
/// `colors`, when not empty, has one colour per point.
/// \throw InputError when normals (or colors, when given) are not one per point.
Splats splat_mesh(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                  const std::vector<Eigen::Vector3f>& colors = {}, double scale = 0.75);

}  // namespace sdm
