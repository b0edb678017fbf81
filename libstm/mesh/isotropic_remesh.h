#pragma once
/// Isotropic remeshing (Botsch & Kobbelt 2004): makes a closed triangle mesh's edges close to one
/// target length and its triangles close to equilateral, without changing its topology.
#include "libstm/mesh/mesh.h"

#include <cmath>
#include <functional>

namespace sdm {

/// Projects a point that lies near the surface back onto it (e.g. Newton steps on an implicit
/// function, or the closest point of a reference mesh). Called from several threads at once: it
/// must not change shared state.
using SurfaceProjection = std::function<Eigen::Vector3d(const Eigen::Vector3d&)>;

/// Each iteration splits edges longer than 4/3 L, collapses edges shorter than 4/5 L (only where
/// the link condition holds and no triangle folds over, so the genus and the number of parts never
/// change), flips edges towards valence 6, moves every vertex tangentially towards the area-weighted
/// centroid of its neighbours and then onto the surface with `project` (when given; otherwise the
/// vertices only slide in their tangent plane). A few final rounds flip edges to the intrinsic
/// Delaunay triangulation, which raises the smallest angles. The mesh must be closed and
/// 2-manifold; it is garbage-collected on return. Deterministic: same input, same output.
void isotropic_remesh(Mesh& mesh, double target_edge_length, int iterations,
                      const SurfaceProjection& project = {});

/// The edge length of an equilateral triangle mesh that covers `area` with about `vertices`
/// vertices (F = 2V, so A = 2V sqrt(3)/4 L^2): unlike the mean edge of a mesh, not inflated by
/// long slivers.
inline double equilateral_edge_length(double area, double vertices) { return std::sqrt(2.0 * area / (std::sqrt(3.0) * vertices)); }

/// The smallest interior angle of any triangle, in degrees.
double min_triangle_angle_degrees(const Mesh& mesh);

}  // namespace sdm
