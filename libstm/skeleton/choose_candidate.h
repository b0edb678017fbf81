#pragma once
/// Choice between the two skeleton candidates of a part: Au et al.'s Laplacian contraction, which
/// keeps the cycles of CAD parts but can pull short limbs into the body, and the medial poles
/// (medial_poles.h), which keep every limb but make sheets of thin walls. A candidate is measured by
/// its cycles against the part's genus, its edges outside the volume, and its tube error (how far
/// the surface is from tubes around the skeleton with the medial radius).
#include "libstm/mesh/inside_mesh.h"
#include "libstm/skeleton/skeleton_graph.h"
#include "libstm/skeleton/skeleton_options.h"

#include <Eigen/Dense>
#include <cmath>

namespace sdm {

/// A refined graph and what the choice compares.
struct SkeletonCandidate {
  SkeletonGraph graph;
  int cycles = 0;             ///< independent cycles (the graph of one part: edges - nodes + 1)
  int outside = 0;            ///< edges not inside the volume
  double error = INFINITY;    ///< tube error / the part's diagonal; infinity when not measured
};

/// How far the skeleton is from explaining the surface (V, F; `poles` row i: the medial pole of
/// vertex i) as tubes around it: the area-weighted mean over vertices of | distance to the graph -
/// medial radius |, the weight of a vertex being the area of its faces. A missing limb leaves its
/// vertices far from every edge; a skeleton through the middle of the volume keeps each vertex at
/// about its inscribed-ball radius. 0 for a mesh of zero area.
double tube_error(const SkeletonGraph& g, const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                  const Eigen::MatrixX3d& poles);

/// A candidate for `graph` (a graph of one connected part): cycles and edges outside `inside`
/// counted; with `poles` given, error = tube_error / diag (diag: the part's bounding-box diagonal).
SkeletonCandidate measure_candidate(SkeletonGraph graph, const InsideMesh& inside, const Eigen::MatrixX3d& V,
                                    const Eigen::MatrixX3i& F, const Eigen::MatrixX3d* poles, double diag);

/// Which candidate a part keeps: options.method when it names one, else (automatic) the better by
/// rank (has edges, cycles == genus, fewer edges outside, smaller error), the medial one's error
/// multiplied by options.medial_handicap. The medial candidate must thus halve the error to win on
/// it alone: where both explain the surface, the contraction's skeleton is the smoother one (the
/// poles of flat caps and of noisy surfaces scatter). With more ends and a better unhandicapped
/// rank it wins too: those ends are limbs the contraction pulled in. Returns
/// SkeletonMethod::contraction or SkeletonMethod::medial.
SkeletonMethod choose_candidate(const SkeletonCandidate& contraction, const SkeletonCandidate& medial, int genus,
                                const SkeletonOptions& options);

}  // namespace sdm
