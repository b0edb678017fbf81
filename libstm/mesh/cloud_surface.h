#pragma once
/// A triangle mesh of the surface a point cloud describes (DESIGN 6.1, "Point clouds"): the zero set
/// of the cloud's IMLS function (point_set_surface.h) traced through the cells of a grid near the
/// points by marching tetrahedra (each cube cut into the six tetrahedra around its main diagonal,
/// the same cut in every cube, so the triangles of neighbouring cubes share their edges' vertices),
/// every vertex then projected onto the zero set. Only tetrahedra whose corners all lie within the
/// support of the points are traced, so a gap in the scan stays a hole; faces away from the points
/// (IMLS's sheets in concave folds) and separate parts far smaller than the whole are dropped.
#include "libstm/geometry/point_set_surface.h"
#include "libstm/mesh/mesh.h"

#include <string>
#include <vector>

namespace sdm {

struct CloudSurfaceOptions {
  PointSetSurfaceOptions surface;
  double cell_spacing = 2.0;  ///< grid cell as a multiple of the cloud's median local spacing
  int max_cells = 400;        ///< at most this many cells along the bounding box's diagonal (a coarser grid otherwise)
  int projections = 3;        ///< projection steps of every vertex onto the zero set
  /// Faces with a vertex farther than this many local spacings from its nearest point are dropped:
  /// IMLS extrapolates each point's plane, and in a concave fold a plane reaches behind another
  /// part of the surface, so the zero set has sheets away from the points there.
  double keep_within = 1.0;
  double min_part = 0.05;     ///< separate parts under this fraction of the diagonal are dropped
};

struct CloudSurfaceStats {
  double cell = 0;              ///< grid cell, model units
  long corners = 0;             ///< grid corners evaluated
  long defined = 0;             ///< of them within the support
  int vertices = 0, faces = 0;  ///< of the mesh
  int boundary_loops = 0;       ///< holes left where the scan has gaps
  int dropped_parts = 0;
  int stray_faces = 0;          ///< faces dropped as away from the points (keep_within)
  double seconds = 0;
};

/// The mesh of the zero set of `points` with `normals` (unit, oriented outward); open where the scan
/// has gaps, manifold, oriented outward.
/// \throw InputError when no surface comes out (normals all
/// pointing one way, a cloud too sparse for its grid).
Mesh cloud_surface(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                   const CloudSurfaceOptions& options = {}, CloudSurfaceStats* stats = nullptr);

}  // namespace sdm
