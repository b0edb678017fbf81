#pragma once
/// Connectivity surgery (Au et al. 2008, "Skeleton extraction by mesh contraction", section 4.2;
/// CGAL's Mean_curvature_flow_skeletonization::convert_to_skeleton is the same step): the contracted
/// mesh, taken as a simplicial complex, loses edges by collapse, cheapest first, until no face is
/// left; the surviving vertices and edges are the curve skeleton, each vertex owning the cluster of
/// vertices collapsed into it. Au et al.'s cost: a shape term (sum of squared distances to the
/// lines of the edges once incident, an edge quadric) and a sampling term (the collapsed edge's
/// length times the length of the edges around the vertex, which keeps segment lengths even).
#include "libstm/mesh/inside_mesh.h"
#include "libstm/skeleton/skeleton_graph.h"
#include "libstm/skeleton/skeleton_options.h"

#include <Eigen/Dense>

namespace sdm {

/// Collapses the contracted mesh (`contracted`: n x 3 positions, `F`: m x 3 faces over them, the
/// input's connectivity) into a graph.
/// - `original`: the n uncontracted positions; a node's position is the centroid of the original
///   positions of its cluster, its `fallback` the contracted position of the surviving vertex.
/// - `inside`: the part's volume. When `genus` > 0, a collapse that would close a loop around a
///   handle (the loop's triangle of cluster centroids, shrunk by 10 %, crosses the surface) is
///   refused, so the graph keeps the part's cycles; a part of genus 0 has no handle to lose.
/// - `options`: shape_weight and sampling_weight weigh the two cost terms.
/// - `stats`, when given: refused_collapses and forced_collapses are increased (forced: every
///   remaining collapse was refused, the cheapest was taken anyway).
/// Returns one node per surviving vertex in vertex order; every vertex of the mesh is in exactly one
/// node's `verts`; an edge joins two nodes whose vertices were joined by an edge of the final
/// complex. Deterministic: ties in cost are broken by vertex index.
SkeletonGraph connectivity_surgery(const Eigen::MatrixX3d& original, const Eigen::MatrixX3d& contracted,
                                   const Eigen::MatrixX3i& F, const InsideMesh& inside, int genus,
                                   const SkeletonOptions& options, SkeletonStats* stats = nullptr);

}  // namespace sdm
