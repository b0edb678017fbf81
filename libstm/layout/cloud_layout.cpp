#include "libstm/layout/cloud_layout.h"

#include "libstm/core/parallel.h"
#include "libstm/core/stopwatch.h"
#include "libstm/geometry/point_kdtree.h"
#include "libstm/mesh/fill_holes.h"

namespace sdm {

Skeleton skeleton_for_surface(const Skeleton& skeleton, const std::vector<Eigen::Vector3d>& points, const Mesh& mesh) {
  Skeleton s = skeleton;
  const PointKdTree tree(points);
  const int nv = int(mesh.n_vertices());
  s.vertex_node.assign(size_t(nv), 0);
  parallel_for(nv, 1024, [&](int v) {
    s.vertex_node[size_t(v)] = skeleton.vertex_node[size_t(tree.nearest_one(point(mesh, mesh.vertex_handle(v))))];
  });
  std::vector<int> owned(s.nodes.size(), 0);
  for (int n : s.vertex_node) ++owned[size_t(n)];
  for (size_t n = 0; n < s.nodes.size(); ++n) {
    if (owned[n]) continue;
    int best = -1;
    double best_d = INFINITY;
    for (int v = 0; v < nv; ++v) {
      const double d = (point(mesh, mesh.vertex_handle(v)) - s.nodes[n]).squaredNorm();
      if (d < best_d && owned[size_t(s.vertex_node[size_t(v)])] > 1) best_d = d, best = v;
    }
    if (best < 0) continue;
    --owned[size_t(s.vertex_node[size_t(best)])];
    s.vertex_node[size_t(best)] = int(n);
    ++owned[n];
  }
  return s;
}

CloudLayout cloud_layout(const PointCloud& cloud, const CloudLayoutOptions& options) {
  CloudLayout out;
  Stopwatch clock;
  out.normals = cloud.normals;
  if (out.normals.size() != cloud.points.size()) {
    report_progress(options.progress, "estimating normals");
    out.normals = estimate_normals(cloud.points);
    out.normals_estimated = true;
  }
  out.normals_seconds = clock.lap();
  // The skeleton (its contraction's factorisations mostly on one core) beside the surface.
  report_progress(options.progress, "extracting the skeleton and tracing the surface");
  Mesh traced;
  run_concurrently(
      [&] {
        const Stopwatch c;
        out.point_skeleton = point_cloud_skeleton(cloud.points, options.skeleton, nullptr, &out.skeleton_stats);
        out.skeleton_seconds = c.seconds();
      },
      [&] {
        const Stopwatch c;
        traced = cloud_surface(cloud.points, out.normals, options.surface, &out.surface_stats);
        out.surface_seconds = c.seconds();
      });
  out.traced_vertices = int(traced.n_vertices());
  out.traced_faces = int(traced.n_faces());
  out.filled_loops = out.surface_stats.boundary_loops;
  out.surface = out.filled_loops ? fill_holes(traced) : std::move(traced);
  clock.lap();
  report_progress(options.progress, "computing the layout");
  LayoutOptions lo = options.layout;
  lo.progress = options.progress;
  out.layout = compute_layout(out.surface, skeleton_for_surface(out.point_skeleton, cloud.points, out.surface), lo);
  out.layout_seconds = clock.lap();
  return out;
}

}  // namespace sdm
