#pragma once
// How far a point correspondence is from a known one: the measure of the shape-correspondence
// literature (Kim, Lipman and Funkhouser 2011, "Blended intrinsic maps"; the tables of BCICP,
// ZoomOut, Smooth Shells, Deep Shells, ULRSSM on FAUST), for correspondences such as the texture
// transfer's (TextureTransfer::correspondence: per target vertex a source face and barycentric
// coordinates) between meshes whose true correspondence is known (FAUST registrations share one
// connectivity: target vertex i truly shows source vertex i).
#include "libstm/mesh/mesh.h"
#include "libstm/registration/carry_skeleton.h"

#include <vector>

namespace sdm {

struct CorrespondenceError {
  // Per target vertex (per entry of the correspondence, in order): the geodesic distance on the
  // source between the assigned source point and the true one, divided by the square root of the
  // source's surface area, times 100 (the literature's unit).
  std::vector<double> geodesic;
  // Per target vertex: the straight distance between the same two points, in % of the source's
  // bounding-box diagonal.
  std::vector<double> euclidean;
  // Their means and 90th percentiles (weighted_quantile with unit weights); 0 when empty.
  double geodesic_mean = 0, geodesic_p90 = 0, euclidean_mean = 0, euclidean_p90 = 0;
};

/// The error of `assigned` (one source point per target vertex) against `truth` (the true source
/// vertex of each target vertex, as many entries). The geodesic is the shortest path along the
/// source's edges from the true vertex to a corner of the assigned point's face, plus the straight
/// segment from that corner to the point (Dijkstra, stopped once no unsettled corner can shorten
/// it): an upper bound of the exact geodesic, exact along a straight line of edges, a few per cent
/// over it on an irregular tessellation (FAUST: at least 3-5 %, docs/BENCHMARKS.md), more on a
/// regular grid (cut along one diagonal: 8 % for a knight's move beside the cuts, 41 % straight
/// across them). A point on a face of the true vertex is at the straight distance. Every target vertex
/// is measured (no sampling), on `threads` threads (0: one per hardware thread; the result does not
/// depend on them). Throws InputError when the counts differ, a face or vertex index lies outside
/// the source, or the source has no area; INFINITY for a point the true vertex cannot reach (another
/// connected part).
CorrespondenceError correspondence_error(const Mesh& source, const std::vector<SourcePoint>& assigned, const std::vector<int>& truth,
                                         int threads = 0);

}  // namespace sdm
