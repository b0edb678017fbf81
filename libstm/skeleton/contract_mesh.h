#pragma once
/// Laplacian contraction (Au et al. 2008, "Skeleton extraction by mesh contraction"; paper 3.1):
/// the surface is shrunk iteratively into a zero-volume shape whose connectivity is still the
/// input's, ready for connectivity surgery (extract_skeleton.h).
#include "libstm/core/progress.h"
#include "libstm/mesh/mesh.h"

#include <Eigen/Dense>
#include <functional>
#include <string>
#include <vector>

namespace sdm {

/// Sparse Cholesky used by the contraction: the project's supernodal LL^T (supernodal_cholesky.h),
/// Eigen's simplicial LDL^T, or CHOLMOD's supernodal LL^T where the build found SuiteSparse
/// (sparse_solver_available tells).
enum class SparseSolver { supernodal, eigen, cholmod };
bool sparse_solver_available(SparseSolver s);

struct ContractOptions {
  SparseSolver solver = SparseSolver::supernodal;
  /// Weights of the Laplacian: cotangent weights of the current (contracted) shape, as Au et al.,
  /// clamped to [cot_min, cot_max] so that degenerating triangles neither blow up nor turn the
  /// Laplacian indefinite. They need well-shaped triangles to start from: on raw CAD meshes (long
  /// thin triangles) they diverge, which is why extract_skeleton contracts an isotropic proxy.
  /// Uniform (umbrella) weights are the fallback for meshes that cannot be remeshed.
  bool cotangent = true;
  double cot_min = 0.0, cot_max = 1e4;
  /// The uniform Laplacian added to the cotangent one, times this (0: cotangent alone). A part
  /// squeezed into a flat sheet (a body's torso) is a fixed point of the cotangent flow: its in-plane
  /// coordinates are harmonic for the sheet's own cotangent weights, so only its rim moves; the
  /// uniform part still pulls every vertex towards its neighbours' centroid (proxy_contraction).
  double uniform_blend = 0.0;
  /// Initial Laplacian weight W_L0 = laplacian_weight * sqrt(total area / mean face area) =
  /// laplacian_weight / sqrt(mean face area) in coordinates of unit total area: Au et al.'s rule,
  /// independent of the model's unit (W_H0 = 1). Small, so that thin limbs contract into their axis
  /// and get pinned before the Laplacian is strong enough to pull them into the body.
  double laplacian_weight = 0.1;
  double laplacian_scale = 2.0;     ///< s_L: W_L is multiplied by it each iteration
  double max_laplacian_growth = 2048;  ///< W_L stops growing at this multiple of W_L0
  double area_ratio_stop = 1e-6;    ///< stop when the area falls below this fraction of the original
  int max_iterations = 20;
  /// Stop once the area is under `stagnant_below` of the original and an iteration no longer halves
  /// it (the surgery copes with the rest), instead of running to max_iterations. At 1e-3 the double
  /// torus stopped at 9.1e-4 after 3 iterations; below it, it goes on to 6e-7 (the target is 1e-4).
  bool stop_when_stagnant = true;
  double stagnant_below = 1e-4;
  /// A vertex whose one-ring area fell below this fraction of its original is pinned.
  double pin_area_ratio = 1e-8;
};

struct ContractResult {
  Eigen::MatrixX3d positions;       ///< contracted positions, one row per vertex, in input units
  int iterations = 0;
  std::vector<double> area_ratio;   ///< total area / original area after each iteration
  double factor_seconds = 0;        ///< time spent in the sparse Cholesky factorisations
};

/// Contracts a closed triangle mesh (V: n x 3, F: m x 3; every vertex in a face). Each iteration
/// solves the normal equations (L^T W_L^2 L + W_H^2) V' = W_H^2 V with L the Laplacian of the
/// current shape (cotangents clamped for degenerate triangles); the sparsity pattern never
/// changes, so the symbolic factorisation is done once. Deterministic; commutes with rigid motions.
ContractResult contract_mesh(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const ContractOptions& options = {},
                             const Progress& progress = nullptr);
ContractResult contract_mesh(const Mesh& mesh, const ContractOptions& options = {}, const Progress& progress = nullptr);

}  // namespace sdm
