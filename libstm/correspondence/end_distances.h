#pragma once
/// Intrinsic features for the spectral refinement of a correspondence between two bodies (zoomout's
/// ZoomOutFeatures): per vertex of each model, the geodesic distance to each end of the matched
/// skeletons (a hand, a foot, the head), at unit area. An end's place is the set of vertices its end
/// node owns (Skeleton::vertex_node of the shared graph), so a few vertices more or less at its
/// border move the distances little. A body slid along itself by the registration (a torso a tenth
/// of sqrt(area) too high) keeps its spectral rows and its closest points, but not its distances to
/// the head and the feet. The geodesic is the shortest path along the edges (Dijkstra from every
/// vertex of the end at once): about 10 % over the exact one on both models alike.
#include "libstm/correspondence/share_skeletons.h"
#include "libstm/mesh/mesh.h"
#include "libstm/registration/zoomout.h"

#include <vector>

namespace sdm {

/// Per vertex of `mesh`, the shortest path along the edges to the nearest of `sources`, divided by
/// the square root of the mesh's area. INFINITY where no path leads (another connected part).
std::vector<double> unit_area_distances(const Mesh& mesh, const std::vector<int>& sources);

/// The features of `source` and `target` for zoomout: one column per end node of the shared graph
/// (degree 1 in skeletons.a and in skeletons.b, owning vertices in both), its unit-area distances on
/// either model; a vertex no path reaches takes the largest finite distance. Empty (no columns)
/// where no end qualifies. Throws InputError when a skeleton's vertex_node does not cover its mesh.
ZoomOutFeatures end_distances(const Mesh& source, const Mesh& target, const SharedSkeletons& skeletons);

}  // namespace sdm
