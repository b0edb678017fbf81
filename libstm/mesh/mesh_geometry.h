#pragma once
/// Geometric measures of a Mesh (the mesh-free formulas are in geometry/differential_geometry.h).
#include "libstm/geometry/differential_geometry.h"
#include "libstm/mesh/mesh.h"

#include <vector>

namespace sdm {

/// Area of face f.
inline double face_area(const Mesh& m, Mesh::FaceHandle f) {
  auto h = m.halfedge_handle(f);
  const Eigen::Vector3d a = point(m, m.from_vertex_handle(h)), b = point(m, m.to_vertex_handle(h)),
                        c = point(m, m.to_vertex_handle(m.next_halfedge_handle(h)));
  return triangle_area(a, b, c);
}

/// Total area of the faces.
double surface_area(const Mesh& mesh);

/// Length of the longest edge (0 for a mesh without edges).
double longest_edge(const Mesh& mesh);

/// Per vertex, a third of the area of its faces (the barycentric dual area), times `factor`.
std::vector<double> vertex_areas(const Mesh& mesh, double factor = 1.0);

/// Per vertex, the length of the shortest path along edges to vertex `from` (Dijkstra): an upper
/// bound of the geodesic distance, within a few per cent of it on a regular tessellation, and
/// unchanged by bending. INFINITY where no path leads.
std::vector<double> edge_path_distances(const Mesh& mesh, int from);

/// A copy of `m` with per-halfedge uv from the orthogonal projection onto its two longest
/// bounding-box axes, each scaled to [0, 1] (a texture for a model without one: benchmarks, tests,
/// the demo's textured humans). Overlapping front and back, as any planar projection.
Mesh with_planar_uv(const Mesh& m);

}  // namespace sdm
