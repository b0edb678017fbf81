#include "libstm/geometry/laplace_basis.h"

#include "libstm/core/errors.h"

#include <Eigen/SparseCholesky>
#include <Spectra/SymEigsShiftSolver.h>
#include <algorithm>
#include <cmath>
#include <numeric>

namespace sdm {

void cotangent_laplacian(const std::vector<Eigen::Vector3d>& points, const std::vector<std::array<int, 3>>& triangles,
                         Eigen::SparseMatrix<double>& stiffness, Eigen::VectorXd& mass) {
  const int n = int(points.size());
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(triangles.size() * 12);
  mass = Eigen::VectorXd::Zero(n);
  for (const auto& t : triangles) {
    for (int c : t)
      if (c < 0 || c >= n) throw InputError("a triangle corner " + std::to_string(c) + " lies outside the " + std::to_string(n) + " points");
    const double area = 0.5 * (points[t[1]] - points[t[0]]).cross(points[t[2]] - points[t[0]]).norm();
    if (!(area > 0)) continue;
    for (int c = 0; c < 3; ++c) {
      // The angle at corner c is opposite edge (i, j).
      const int i = t[(c + 1) % 3], j = t[(c + 2) % 3];
      const Eigen::Vector3d u = points[i] - points[t[c]], v = points[j] - points[t[c]];
      const double w = 0.5 * u.dot(v) / u.cross(v).norm();
      entries.emplace_back(i, j, -w), entries.emplace_back(j, i, -w);
      entries.emplace_back(i, i, w), entries.emplace_back(j, j, w);
      mass[t[c]] += area / 3;
    }
  }
  stiffness.resize(n, n);
  stiffness.setFromTriplets(entries.begin(), entries.end());
}

namespace {

// y = (A - sigma I)^-1 x for A = M^-1/2 L M^-1/2: y = M^1/2 (L - sigma M)^-1 M^1/2 x, one sparse
// LDLT factorisation per shift (Spectra's user-supplied shift-solve operation).
class ShiftInvertOperation {
 public:
  using Scalar = double;
  ShiftInvertOperation(const Eigen::SparseMatrix<double>& stiffness, const Eigen::VectorXd& mass)
      : stiffness_(stiffness), root_mass_(mass.cwiseSqrt()) {}
  Eigen::Index rows() const { return stiffness_.rows(); }
  Eigen::Index cols() const { return stiffness_.cols(); }
  void set_shift(double sigma) {
    Eigen::SparseMatrix<double> shifted = stiffness_;
    for (Eigen::Index i = 0; i < shifted.rows(); ++i) shifted.coeffRef(i, i) -= sigma * root_mass_[i] * root_mass_[i];
    solver_.compute(shifted);
    if (solver_.info() != Eigen::Success) throw InputError("the Laplacian could not be factorised (a degenerate mesh)");
  }
  void perform_op(const double* x_in, double* y_out) const {
    const Eigen::Map<const Eigen::VectorXd> x(x_in, rows());
    Eigen::Map<Eigen::VectorXd> y(y_out, rows());
    y = root_mass_.cwiseProduct(solver_.solve(Eigen::VectorXd(root_mass_.cwiseProduct(x))));
  }

 private:
  const Eigen::SparseMatrix<double>& stiffness_;
  Eigen::VectorXd root_mass_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver_;
};

}  // namespace

LaplaceBasis laplace_basis(const std::vector<Eigen::Vector3d>& points, const std::vector<std::array<int, 3>>& triangles, int k) {
  const int n = int(points.size());
  if (k < 1 || k >= n) throw InputError("the Laplace basis needs 1 <= k < vertices, not k = " + std::to_string(k) + " of " + std::to_string(n));
  LaplaceBasis basis;
  Eigen::SparseMatrix<double> stiffness;
  cotangent_laplacian(points, triangles, stiffness, basis.mass);
  const double area = basis.mass.sum();
  if (!(area > 0)) throw InputError("the mesh has no area, so it has no Laplace basis");
  // A vertex no face touches gets a tiny mass and a unit tie to nothing: it stays out of the way.
  for (int i = 0; i < n; ++i)
    if (!(basis.mass[i] > 0)) basis.mass[i] = 1e-12 * area / n;
  // Solved at unit area (the eigenvalues then lie in the same range on every mesh), scaled back.
  const Eigen::VectorXd unit_mass = basis.mass / area;
  ShiftInvertOperation op(stiffness, unit_mass);
  // A few more than asked, the largest dropped: Lanczos may converge to all but one copy of a
  // repeated eigenvalue (a sphere's l = 3, seven times) and take the next one instead.
  const int nev = std::min(n - 1, k + std::max(4, k / 10)), ncv = std::min(n, std::max(2 * nev + 1, nev + 20));
  Spectra::SymEigsShiftSolver<ShiftInvertOperation> eigs(op, nev, ncv, -1e-3);
  eigs.init();
  eigs.compute(Spectra::SortRule::LargestMagn, 1000, 1e-8);
  if (eigs.info() != Spectra::CompInfo::Successful)
    throw InputError("the Laplace eigenvalues did not converge (" + std::to_string(k) + " of a mesh of " + std::to_string(n) + " vertices)");
  const Eigen::VectorXd values = eigs.eigenvalues();
  const Eigen::MatrixXd vectors = eigs.eigenvectors();
  std::vector<int> order(static_cast<size_t>(nev));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return values[a] < values[b]; });
  basis.values.resize(k);
  basis.vectors.resize(n, k);
  const Eigen::VectorXd inverse_root = unit_mass.cwiseSqrt().cwiseInverse() / std::sqrt(area);
  for (int i = 0; i < k; ++i) {
    basis.values[i] = values[order[size_t(i)]] / area;
    Eigen::VectorXd phi = vectors.col(order[size_t(i)]).cwiseProduct(inverse_root);
    // A deterministic sign: the largest entry positive.
    Eigen::Index at;
    phi.cwiseAbs().maxCoeff(&at);
    if (phi[at] < 0) phi = -phi;
    basis.vectors.col(i) = phi;
  }
  return basis;
}

}  // namespace sdm
