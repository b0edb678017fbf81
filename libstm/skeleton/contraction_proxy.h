#pragma once
/// The contraction proxy of a large part: the part isotropically remeshed to a bounded number of
/// vertices (projected onto its surface), contracted and cut in its place; the part's own vertices
/// are then mapped to the proxy skeleton's nodes. Well-shaped triangles keep the cotangent Laplacian
/// stable and the size bounds the cost.
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/skeleton/skeleton_graph.h"

#include <Eigen/Dense>
#include <vector>

namespace sdm {

/// The part (V, F; closed) remeshed isotropically to about `target_vertices` vertices (at least 4),
/// its vertices projected onto the part's surface; written to XV, XF. An equilateral mesh of area A
/// and edge length l has about 2 A / (sqrt(3) l^2) vertices. `surface`, when given, is a BVH of
/// (V, F) to project with (the extraction's own, so that none is built twice).
void make_proxy(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, int target_vertices, Eigen::MatrixX3d& XV,
                Eigen::MatrixX3i& XF, const TriangleBvh* surface = nullptr);

/// The node of `g` (a graph over the proxy XV, XF: g.verts index XV) for every vertex of the part
/// (V, F). A vertex goes to the node of the nearest corner of its closest proxy face, unless that
/// face looks the other way (the far side of a thin sheet): then to the nearest proxy vertex whose
/// normal agrees. A node that receives no vertex takes the nearest vertex of a node that owns
/// several, so every node owns at least one (when the part has enough vertices).
std::vector<int> map_to_nodes(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::MatrixX3d& XV,
                              const Eigen::MatrixX3i& XF, const SkeletonGraph& g);

}  // namespace sdm
