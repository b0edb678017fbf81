#pragma once
// Laplacian contraction (Au et al. 2008, "Skeleton extraction by mesh contraction"; paper 3.1):
// the surface is shrunk iteratively into a zero-volume shape whose connectivity is still the
// input's, ready for connectivity surgery (extract_skeleton.h).
#include "libstm/mesh.h"

#include <Eigen/Dense>
#include <functional>
#include <string>
#include <vector>

namespace stm {

struct ContractOptions {
  // Weights of the Laplacian. Au et al. use cotangent weights of the current shape; on meshes
  // with long thin triangles (CAD models such as anchor or rotor) those weights blow up as the
  // shape degenerates and the contraction diverges even with clamping and pinning. Uniform
  // (umbrella) weights stay bounded and contract every test model into its volume; the node
  // positions come from the original vertices anyway (refinement), so the tangential drift of
  // uniform weights does not show in the skeleton.
  bool cotangent = false;
  // Initial Laplacian weight W_L0 = laplacian_weight * sqrt(total area / mean face area). The
  // cotangent Laplacian has no unit, so this is Au et al.'s 1/sqrt(mean face area) made
  // independent of the model's unit (W_H0 = 1); it grows with resolution because finer meshes
  // need a stronger Laplacian to move a cross-section by the same amount.
  double laplacian_weight = 1.0;
  double laplacian_scale = 2.0;     // s_L: W_L is multiplied by it each iteration
  double max_laplacian_growth = 2048;  // W_L stops growing at this multiple of W_L0
  double area_ratio_stop = 1e-6;    // stop when the area falls below this fraction of the original
  int max_iterations = 20;
  // A vertex whose one-ring area fell below this fraction of its original is pinned.
  double pin_area_ratio = 1e-8;
};

struct ContractResult {
  Eigen::MatrixX3d positions;       // contracted positions, one row per vertex, in input units
  int iterations = 0;
  std::vector<double> area_ratio;   // total area / original area after each iteration
  double factor_seconds = 0;        // time spent in the sparse Cholesky factorisations
};

using Progress = std::function<void(const std::string&)>;

// Contracts a closed triangle mesh (V: n x 3, F: m x 3; every vertex in a face). Each iteration
// solves the normal equations (L^T W_L^2 L + W_H^2) V' = W_H^2 V with L the Laplacian of the
// current shape (cotangents clamped for degenerate triangles); the sparsity pattern never
// changes, so the symbolic factorisation is done once. Deterministic; commutes with rigid motions.
ContractResult contract_mesh(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const ContractOptions& options = {},
                             const Progress& progress = nullptr);
ContractResult contract_mesh(const Mesh& mesh, const ContractOptions& options = {}, const Progress& progress = nullptr);

}  // namespace stm
