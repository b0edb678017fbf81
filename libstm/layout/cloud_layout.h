#pragma once
/// The skeleton texture map of a point cloud (DESIGN 6.1, "Point clouds"): the cloud's own skeleton
/// (point_skeleton.h, each point keeping its node) and the surface its points describe
/// (cloud_surface.h), its gaps closed by faired patches (fill_holes.h) so that the map and its decode
/// are closed; every vertex of that surface takes the node of its nearest point, and the layout is
/// computed for it as for a mesh (compute_layout.h).
#include "libstm/core/progress.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/mesh/cloud_surface.h"
#include "libstm/mesh/point_cloud.h"
#include "libstm/skeleton/point_skeleton.h"

namespace sdm {

struct CloudLayoutOptions {
  CloudSurfaceOptions surface;
  PointSkeletonOptions skeleton;
  LayoutOptions layout;
  Progress progress;
};

struct CloudLayout {
  std::vector<Eigen::Vector3d> normals;  ///< the cloud's normals, or those estimated (estimate_normals)
  bool normals_estimated = false;
  Mesh surface;               ///< the traced surface, its holes filled: closed
  int traced_vertices = 0;    ///< surface's first vertices are traced on the points, the rest fill its gaps
  int traced_faces = 0;
  int filled_loops = 0;       ///< gaps closed
  Skeleton point_skeleton;    ///< per point (the cloud's order) its node
  Layout layout;              ///< of `surface`
  CloudSurfaceStats surface_stats;
  PointSkeletonStats skeleton_stats;
  double normals_seconds = 0, surface_seconds = 0, skeleton_seconds = 0, layout_seconds = 0;
};

/// The layout of `cloud` (prepared: prepare_cloud).
/// \throw InputError when no surface or no skeleton
/// comes from the points, or the layout refuses them.
CloudLayout cloud_layout(const PointCloud& cloud, const CloudLayoutOptions& options = {});

/// `skeleton` (per point of `points` its node) given to the vertices of `mesh`: each takes its
/// nearest point's node; a node no vertex takes gets the vertex nearest to it.
Skeleton skeleton_for_surface(const Skeleton& skeleton, const std::vector<Eigen::Vector3d>& points, const Mesh& mesh);

}  // namespace sdm
