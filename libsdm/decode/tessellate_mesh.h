#pragma once
/// Crack-free tessellation of a triangle mesh with a rate per face, by OpenSubdiv's Bfr
/// tessellation patterns. Every edge gets one rate (the larger of its two faces'), so the points
/// along a shared edge are the same for both faces and the result is welded into one mesh: a closed
/// 2-manifold base gives a closed 2-manifold output whatever the mix of rates.
#include <Eigen/Dense>
#include <vector>

namespace sdm {

struct Tessellation {
  Eigen::MatrixX3i triangles;          ///< indices into the points below, oriented as their base face
  std::vector<int> point_face;         ///< base face each point is evaluated in (one canonical face
                                       ///< for points on shared edges and corners)
  std::vector<Eigen::Vector3d> point_bary;  ///< barycentric coordinates in that face (corners 0, 1, 2)
  std::vector<int> triangle_face;      ///< base face each output triangle comes from
};

/// base: F x 3 triangles of a consistently oriented mesh. rate[f] >= 1: each edge of face f is cut
/// into rate[f] pieces (uniform rate r gives r*r triangles per face).
Tessellation tessellate_mesh(const Eigen::MatrixX3i& base, const std::vector<int>& rate);

}  // namespace sdm
