#pragma once
/// Refinement of a surgery's graph (Au et al. 2008, section 4.3, "embedding refinement"; CGAL's
/// skeletonization leaves the same step to the caller): nodes move to the centre of the original
/// vertices they own, short end branches and short edges are merged, and the graph is kept inside
/// the volume (nodes pulled in, crossing edges bent through a medial pole). Each step below can be
/// called alone; extract_skeleton runs refine_skeleton, centre_junctions (when asked),
/// bend_crossing_edges and, on the chosen candidate, split_lone_node.
#include "libstm/mesh/inside_mesh.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/skeleton/skeleton_graph.h"
#include "libstm/skeleton/skeleton_options.h"

#include <Eigen/Dense>

namespace sdm {

/// Merges short end branches and short edges of `g` and places its nodes. `original`: the part's
/// vertices (g.verts index them), `inside` and `surface`: the part's volume and a BVH over its
/// surface, `diag`: the part's bounding-box diagonal. Options used: min_branch (fraction of diag),
/// prune_radius, segment_radius.
/// - An end branch goes into its junction when it is shorter than min_branch * diag or than
///   prune_radius times the junction's distance to the surface (a bump of the junction's
///   cross-section, not a limb).
/// - An edge goes when shorter than segment_radius times the smaller mean distance of its ends to
///   their vertices (or than min_branch * diag); the node with more vertices stays. A merge that
///   would leave a cycle with fewer than three segments is skipped.
/// - A merged node sits at the centroid of its vertices when that point and its edges lie inside,
///   else at one of the merged nodes. Last, every node whose position or edges leave the volume is
///   pulled toward its `fallback`, then along its edges, until they do not (unchanged when nothing
///   works).
/// Nodes keep their order; a node stays at the centroid of its vertices unless it had to move.
void refine_skeleton(SkeletonGraph& g, const Eigen::MatrixX3d& original, const InsideMesh& inside,
                     const TriangleBvh& surface, double diag, const SkeletonOptions& options);

/// Junctions (degree >= 3) go to the pole of widest ball among their vertices' medial poles (`poles`
/// row i: the pole of `original` row i), when that pole lies within `reach` of its radii and the
/// move keeps the node and its edges inside. The cluster a surgery leaves at a junction changes with
/// the tessellation, the widest ball of the crossing region much less, so two models of one shape
/// get junctions in the same place (what texture transfer needs).
void centre_junctions(SkeletonGraph& g, const Eigen::MatrixX3d& original, const Eigen::MatrixX3d& poles,
                      const InsideMesh& inside, double reach);

/// An edge that crosses the surface (a spur cutting a corner of a thin wall) is bent through a new
/// node at the medial pole (`poles`, one per vertex) that sees both ends from inside with the
/// shortest detour, taken from a node owning at least two vertices; that vertex moves to the new
/// node. With no such pole, an end branch behind the edge goes into the node on the edge's other
/// side (a limb that cannot be reached from inside is not one the layout could use). Edges that
/// cannot be fixed either way stay.
void bend_crossing_edges(SkeletonGraph& g, const InsideMesh& inside, const Eigen::MatrixX3d& poles);

/// A graph of a single node owning at least two vertices (a ball-like part, where every edge was
/// shorter than the local radius) becomes two nodes on the principal axis of the vertices
/// (`original`), one edge between them inside the volume, each owning the vertices on its side.
/// Other graphs are left alone. Without it the layout would give the part no segment.
void split_lone_node(SkeletonGraph& g, const Eigen::MatrixX3d& original, const InsideMesh& inside);

}  // namespace sdm
