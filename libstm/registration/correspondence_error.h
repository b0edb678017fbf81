#pragma once
/// How far a point correspondence is from a known one: the measure of the shape-correspondence
/// literature (Kim, Lipman and Funkhouser 2011, "Blended intrinsic maps"; the tables of BCICP,
/// ZoomOut, Smooth Shells, Deep Shells, ULRSSM), for correspondences such as the texture
/// transfer's (TextureTransfer::correspondence: per target vertex a source face and barycentric
/// coordinates) between meshes whose true correspondence is known (registrations that share one
/// connectivity: target vertex i truly shows source vertex i).
#include "libstm/mesh/mesh.h"
#include "libstm/registration/carry_skeleton.h"

#include <vector>

namespace sdm {

struct CorrespondenceError {
  /// Per target vertex (per entry of the correspondence, in order): the geodesic distance on the
  /// source between the assigned source point and the true one, divided by the square root of the
  /// source's surface area, times 100 (the literature's unit).
  std::vector<double> geodesic;
  /// Per target vertex: the straight distance between the same two points, in % of the source's
  /// bounding-box diagonal.
  std::vector<double> euclidean;
  /// Their means and 90th percentiles (weighted_quantile with unit weights); 0 when empty.
  double geodesic_mean = 0, geodesic_p90 = 0, euclidean_mean = 0, euclidean_p90 = 0;
};

/// The error of `assigned` (one source point per target vertex) against `truth` (the true source
/// vertex of each target vertex, as many entries). The geodesic is the shortest path from the true
/// vertex to the point through the source's surface graph with `steiner` points on every edge
/// (Lanthier, Maheshwari and Sack 1997: the vertices and points of each face joined by straight
/// segments across it), the last leg straight across the point's face (A* towards the point,
/// stopped once no unsettled node can shorten it). Every such path lies on the surface, so it is an upper bound of
/// the exact geodesic that tightens as `steiner` grows: exact along a straight line of edges and
/// wherever the geodesic passes through the edge points; the default 5 points come within about
/// 1 % of the limit (docs/BENCHMARKS.md, correspondence error). `steiner` = 0 is the
/// path along the edges alone, which overestimates, most on a regular grid. A point on a face of the true vertex
/// is at the straight distance. Every target vertex is measured (no sampling), on `threads` threads
/// (0: one per hardware thread; the result does not depend on them).
/// \throw InputError when the
/// counts differ, a face or vertex index lies outside the source, the source has no area or
/// `steiner` < 0; INFINITY for a point the true vertex cannot reach (another connected part).
CorrespondenceError correspondence_error(const Mesh& source, const std::vector<SourcePoint>& assigned, const std::vector<int>& truth,
                                         int threads = 0, int steiner = 5);

}  // namespace sdm
