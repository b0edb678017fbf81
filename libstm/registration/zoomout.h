#pragma once
/// Spectral refinement of a point correspondence: ZoomOut (Melzi, Ren, Rodola, Sharma, Wonka and
/// Ovsjanikov 2019, "ZoomOut: spectral upsampling for efficient shape correspondence"). The map
/// (per target vertex a source point) is turned into a functional map C = Phi_T^+ Pi Phi_S between
/// the first k Laplace-Beltrami eigenfunctions of both meshes (laplace_basis, both at unit area;
/// Phi_T^+ = Phi_T^T M_T), and back into a point map by nearest neighbours: each target vertex takes
/// the source vertex whose row of Phi_S is nearest to its row of Phi_T C (Pi Phi_S = Phi_T C); k
/// grows by `step` from k_start to k_end. Optionally, as in Smooth Shells (Eisenberger et al. 2020)
/// and the discrete solvers of Ren et al. 2021, the search runs in the product of the spectral and
/// the spatial coordinates (on the source: a candidate's position against the start's point, so that
/// the refinement stays near where the start put each vertex), and only among the source vertices
/// near the start's point. Each step's C is made orthogonal (an isometry's). Finally each target vertex takes the point of a
/// face around its source vertex nearest in those coordinates (a vertex-to-point map). DECISIONS 5,
/// "Spectral refinement".
#include "libstm/geometry/laplace_basis.h"
#include "libstm/mesh/mesh.h"
#include "libstm/registration/carry_skeleton.h"

#include <Eigen/Dense>
#include <vector>

namespace sdm {

struct ZoomOutOptions {
  /// The defaults are the best of the variants measured (DECISIONS 5, "Spectral refinement").
  int k_start = 20, k_end = 150, step = 20;  ///< the basis sizes, k_start, k_start + step, ..., k_end
  /// The weight of the spatial coordinates against the spectral ones in the nearest-neighbour
  /// search (both meshes at unit area; 0: spectral alone).
  double spatial_weight = 50;
  double spatial_weight_end = -1;  ///< the weight at k_end (linear in k between; < 0: spatial_weight throughout)
  int final_steps = 4;             ///< steps more at k_end
  /// Each target vertex searches only the source vertices within this distance (at unit area) of
  /// its start's point on the source (0: every source vertex).
  double window = 0.06;
  double window_end = -1;  ///< the window at k_end (linear in k between; < 0: window throughout)
  /// The spatial coordinates and the window of each target vertex around the point this share of
  /// the way from its start's source point to its current one (the previous step's map): 0 the
  /// start, 1 the current map, which may move further than the window in steps. Off (BENCHMARKS,
  /// "A refinement anchor that follows the map").
  double follow = 0;
  /// Each step also maps the source's vertices to the target's (nearest rows of Phi_T to those of
  /// Phi_S C^T) and C is the mean of both maps' functional maps (Ren et al. 2021's bidirectional
  /// ZoomOut).
  bool bidirectional = true;
  /// C replaced at each step by its nearest orthogonal matrix (U V^T of its SVD): the functional map
  /// of an isometry between the unit-area bases is orthogonal (Ovsjanikov et al. 2012; the
  /// orthogonality term of Ren et al. 2021's discrete solver, here as a projection; DECISIONS 5,
  /// "Spectral refinement").
  bool orthogonal = true;
  /// The weight of the intrinsic features (ZoomOutFeatures, at unit area) in the same search: 0
  /// leaves them out (the default): with the distances to the skeletons' ends (end_distances) they
  /// help some pairs and hurt others (docs/BENCHMARKS.md, "End distances in the spectral refinement").
  double feature_weight = 0;
  double feature_weight_end = -1;  ///< the weight at k_end (linear in k between; < 0: feature_weight throughout)
  /// The pointwise map of each step from the energy of the discrete solver of Ren, Melzi, Wonka and
  /// Ovsjanikov 2021 (libstm/registration/discrete_map_energy.h): the weights of bijectivity
  /// (C12 C21 = I), orthogonality (C12 C12^T = I) and Laplacian commutativity beside properness (1),
  /// all in one nearest-neighbour search in both directions. Any above 0: C12 and C21 each from its own
  /// direction's map (not averaged). All 0 (the default): ZoomOut's step alone (BENCHMARKS, "The
  /// discrete solver's energy in the refinement").
  double bijectivity_weight = 0, orthogonality_weight = 0, commutativity_weight = 0;
  int threads = 0;  ///< 0: one per hardware thread; the result does not depend on it
};

/// Intrinsic features that the two meshes share, searched beside the spectral and the spatial
/// coordinates: per vertex of each, the same columns (say the geodesic distances, at unit area, to
/// matched places: end_distances). Empty: none.
struct ZoomOutFeatures {
  Eigen::MatrixXd source, target;  ///< source vertices x m, target vertices x m
};

/// The mesh's points and triangles as laplace_basis takes them.
LaplaceBasis mesh_laplace_basis(const Mesh& mesh, int k);

/// Refines `start` (one source point per target vertex) by ZoomOut. `source_basis` and
/// `target_basis` are the meshes' Laplace bases (at least k_end functions each, any units);
/// `features` (with options.feature_weight > 0) join the search. Deterministic.
/// \throw InputError
/// when the sizes disagree, a basis has fewer than k_end functions or k_start < 1.
std::vector<SourcePoint> zoomout(const Mesh& source, const LaplaceBasis& source_basis, const Mesh& target,
                                 const LaplaceBasis& target_basis, const std::vector<SourcePoint>& start,
                                 const ZoomOutOptions& options = {}, const ZoomOutFeatures& features = {});

/// zoomout with both meshes' bases computed here (k_end functions each, the two on two threads).
std::vector<SourcePoint> refine_correspondence(const Mesh& source, const Mesh& target, const std::vector<SourcePoint>& start,
                                               const ZoomOutOptions& options = {});

}  // namespace sdm
