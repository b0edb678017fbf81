#pragma once
/// The Laplace-Beltrami eigenbasis of a triangle mesh: the cotangent stiffness matrix (Pinkall and
/// Polthier 1993; Meyer et al. 2003) and the lumped (barycentric) mass, and the eigenpairs of
/// L phi = lambda M phi with the smallest eigenvalues, found by shift-invert Lanczos (Spectra's
/// SymEigsShiftSolver on M^-1/2 L M^-1/2, each step one solve with a sparse LDLT of L - sigma M).
/// The basis of functional maps and of their spectral refinement (libstm/registration/zoomout.h;
/// DECISIONS 5, "Spectral refinement").
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <array>
#include <vector>

namespace sdm {

/// The mesh as the geometry layer takes it: points and the triangles' corner indices.
/// The cotangent stiffness L (symmetric, positive semi-definite, rows summing to 0: L_ij =
/// -(cot alpha_ij + cot beta_ij) / 2 over the two angles opposite edge ij) and the lumped mass
/// (a third of the area of each face at each of its corners). Degenerate faces add nothing.
/// \throw InputError when a corner index lies outside `points`.
void cotangent_laplacian(const std::vector<Eigen::Vector3d>& points, const std::vector<std::array<int, 3>>& triangles,
                         Eigen::SparseMatrix<double>& stiffness, Eigen::VectorXd& mass);

struct LaplaceBasis {
  Eigen::VectorXd values;   ///< the k smallest eigenvalues, ascending (the first about 0 on a closed mesh)
  Eigen::MatrixXd vectors;  ///< n x k, column i the eigenfunction of values[i], M-orthonormal
  Eigen::VectorXd mass;     ///< the lumped mass per vertex (sums to the area)
};

/// The `k` Laplace-Beltrami eigenpairs of the mesh with the smallest eigenvalues, in the mesh's own
/// units (a sphere of radius R: l (l + 1) / R^2, multiplicity 2 l + 1). Deterministic. Throws
/// InputError when k < 1, k >= the vertex count, the mesh has no area, or the solver does not
/// converge (a mesh with more connected parts than k, or degenerate beyond repair).
LaplaceBasis laplace_basis(const std::vector<Eigen::Vector3d>& points, const std::vector<std::array<int, 3>>& triangles, int k);

}  // namespace sdm
