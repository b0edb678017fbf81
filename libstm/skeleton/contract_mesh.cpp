#include "libstm/skeleton/contract_mesh.h"

#include "libstm/core/errors.h"
#include "libstm/geometry/supernodal_cholesky.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#ifdef SDM_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace sdm {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// SupernodalCholesky behind the interface of Eigen's factorisations, for the iteration below.
class SupernodalSolver {
 public:
  void analyzePattern(const Eigen::SparseMatrix<double>& A) { llt_.analyze(A); }
  void factorize(const Eigen::SparseMatrix<double>& A) { ok_ = llt_.factorize(A); }
  Eigen::ComputationInfo info() const { return ok_ ? Eigen::Success : Eigen::NumericalIssue; }
  Eigen::MatrixX3d solve(const Eigen::MatrixX3d& B) const { return llt_.solve(B); }

 private:
  SupernodalCholesky llt_;
  bool ok_ = false;
};

// Cotangent of the angle between u and v, clamped: contracted triangles degenerate, and an
// unbounded weight would make the system singular.
double clamped_cot(const Eigen::Vector3d& u, const Eigen::Vector3d& v, double lo, double hi) {
  const double c = u.dot(v);
  const double s = u.cross(v).norm();
  if (s <= std::abs(c) / hi) return c >= 0 ? hi : lo;
  return std::clamp(c / s, lo, hi);
}

}  // namespace

ContractResult contract_mesh(const Eigen::MatrixX3d& V0, const Eigen::MatrixX3i& F, const ContractOptions& opt,
                             const Progress& progress) {
  const int n = int(V0.rows()), m = int(F.rows());
  ContractResult res;
  res.positions = V0;
  if (n == 0 || m == 0) return res;

  // Closed one-rings R_i = {i} + neighbours, sorted: row i of L lives on R_i.
  std::vector<std::vector<int>> ring(n);
  for (int i = 0; i < n; ++i) ring[i].push_back(i);
  for (int f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      ring[a].push_back(b), ring[b].push_back(a);
    }
  for (auto& r : ring) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  }
  auto slot_in = [&](int i, int j) { return int(std::lower_bound(ring[i].begin(), ring[i].end(), j) - ring[i].begin()); };
  // For every face edge (opposite corner k): where each end sits in the other's ring.
  std::vector<std::array<int, 6>> face_slots(m);
  for (int f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, (k + 1) % 3), b = F(f, (k + 2) % 3);
      face_slots[f][2 * k] = slot_in(a, b);
      face_slots[f][2 * k + 1] = slot_in(b, a);
    }

  // Pattern of the lower triangle of L^T L (+ diagonal): every pair inside one closed ring.
  std::vector<Eigen::Triplet<double>> trip;
  size_t pairs = 0;
  for (const auto& r : ring) pairs += r.size() * (r.size() + 1) / 2;
  trip.reserve(pairs);
  for (const auto& r : ring)
    for (size_t a = 0; a < r.size(); ++a)
      for (size_t b = 0; b <= a; ++b) trip.emplace_back(r[a], r[b], 0.0);  // r sorted: r[a] >= r[b]
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(trip.begin(), trip.end());
  A.makeCompressed();
  trip.clear();
  trip.shrink_to_fit();
  // Value slot of every ring pair, so each iteration fills A without searching.
  std::vector<int> pair_slot;
  pair_slot.reserve(pairs);
  auto value_index = [&](int row, int col) {
    const int* begin = A.innerIndexPtr() + A.outerIndexPtr()[col];
    const int* end = A.innerIndexPtr() + A.outerIndexPtr()[col + 1];
    return int(std::lower_bound(begin, end, row) - A.innerIndexPtr());
  };
  for (const auto& r : ring)
    for (size_t a = 0; a < r.size(); ++a)
      for (size_t b = 0; b <= a; ++b) pair_slot.push_back(value_index(r[a], r[b]));
  std::vector<int> diag_slot(n);
  for (int i = 0; i < n; ++i) diag_slot[i] = value_index(i, i);

  Eigen::MatrixX3d V = V0;
  auto face_areas = [&](const Eigen::MatrixX3d& P, std::vector<double>& fa, std::vector<double>& va) {
    fa.assign(m, 0.0);
    va.assign(n, 0.0);
    double total = 0;
    for (int f = 0; f < m; ++f) {
      const Eigen::Vector3d a = P.row(F(f, 0)), b = P.row(F(f, 1)), c = P.row(F(f, 2));
      fa[f] = 0.5 * (b - a).cross(c - a).norm();
      total += fa[f];
      for (int k = 0; k < 3; ++k) va[F(f, k)] += fa[f];
    }
    return total;
  };
  std::vector<double> fa, va0, va;
  const double area0 = face_areas(V, fa, va0);
  if (!(area0 > 0)) throw InputError("cannot contract a mesh of zero area");

  const double WL0 = opt.laplacian_weight * std::sqrt(double(m));
  double WL = WL0;
  Eigen::VectorXd WH = Eigen::VectorXd::Ones(n);
  std::vector<std::vector<double>> lrow(n);
  for (int i = 0; i < n; ++i) lrow[i].assign(ring[i].size(), 0.0);

  std::vector<char> pinned(n, 0);
  int npinned = 0;
  double ratio = 1.0;
  // The iterations, over either sparse Cholesky (same pattern every iteration: one analysis).
  auto iterate = [&](auto& solver) {
  bool analysed = false;
  for (int it = 0; it < opt.max_iterations && ratio > opt.area_ratio_stop; ++it) {
    // Laplacian of the current shape (uniform weights count each face corner 1/2, so that an
    // interior edge weighs 1 like the cotangent weights of an equilateral mesh).
    for (auto& r : lrow) std::fill(r.begin(), r.end(), 0.0);
    for (int f = 0; f < m; ++f) {
      for (int k = 0; k < 3; ++k) {
        const int c = F(f, k), a = F(f, (k + 1) % 3), b = F(f, (k + 2) % 3);
        const double w = opt.cotangent ? clamped_cot(V.row(a) - V.row(c), V.row(b) - V.row(c), opt.cot_min, opt.cot_max) : 0.5;
        lrow[a][face_slots[f][2 * k]] += w;
        lrow[b][face_slots[f][2 * k + 1]] += w;
      }
    }
    for (int i = 0; i < n; ++i) {
      double s = 0;
      const int self = slot_in(i, i);
      for (size_t a = 0; a < ring[i].size(); ++a)
        if (int(a) != self) s += lrow[i][a];
      lrow[i][self] = -s;
    }
    // A = W_L^2 L^T L + W_H^2.
    double* val = A.valuePtr();
    std::fill(val, val + A.nonZeros(), 0.0);
    const double wl2 = WL * WL;
    size_t p = 0;
    for (int i = 0; i < n; ++i) {
      const auto& l = lrow[i];
      if (pinned[i]) {  // a collapsed one-ring's cotangents are noise; its row would fling its neighbours
        p += l.size() * (l.size() + 1) / 2;
        continue;
      }
      for (size_t a = 0; a < l.size(); ++a) {
        const double la = wl2 * l[a];
        for (size_t b = 0; b <= a; ++b) val[pair_slot[p++]] += la * l[b];
      }
    }
    for (int i = 0; i < n; ++i) val[diag_slot[i]] += WH[i] * WH[i];
    // Pinned vertices are eliminated (their rows become identity) rather than weighted: with
    // W_L growing geometrically, no finite W_H would keep them in place.
    Eigen::MatrixX3d rhs = WH.cwiseAbs2().asDiagonal() * V;
    if (npinned) {
      for (int col = 0; col < n; ++col)
        for (int q = A.outerIndexPtr()[col]; q < A.outerIndexPtr()[col + 1]; ++q) {
          const int row = A.innerIndexPtr()[q];
          if (!pinned[row] && !pinned[col]) continue;
          if (row == col) {
            val[q] = 1.0;
            continue;
          }
          if (!pinned[row]) rhs.row(row) -= val[q] * V.row(col);
          if (!pinned[col]) rhs.row(col) -= val[q] * V.row(row);
          val[q] = 0.0;
        }
      for (int i = 0; i < n; ++i)
        if (pinned[i]) rhs.row(i) = V.row(i);
    }
    const auto t0 = Clock::now();
    if (!analysed) solver.analyzePattern(A), analysed = true;
    solver.factorize(A);
    res.factor_seconds += seconds_since(t0);
    if (solver.info() != Eigen::Success) break;  // keep the last good shape
    Eigen::MatrixX3d Vn = solver.solve(rhs);
    if (!Vn.allFinite()) break;
    V = Vn;

    const double area = face_areas(V, fa, va);
    const double previous = ratio;
    ratio = area / area0;
    res.area_ratio.push_back(ratio);
    res.iterations = it + 1;
    if (progress) {
      char line[160];
      std::snprintf(line, sizeof line, "contraction iteration %d: area ratio %.3g, W_L %.3g, pinned %d", it + 1, ratio, WL, npinned);
      progress(line);
    }
    // Au et al.: W_H,i = sqrt(A_i^0 / A_i^t); a collapsed one-ring is pinned where it is.
    for (int i = 0; i < n; ++i) {
      const double r = va[i] / va0[i];
      if (r < opt.pin_area_ratio && !pinned[i]) pinned[i] = 1, ++npinned;
      WH[i] = pinned[i] ? 1.0 : std::sqrt(1.0 / r);
    }
    WL = std::min(WL * opt.laplacian_scale, WL0 * opt.max_laplacian_growth);
    // Stagnation: once the shape is thin, an iteration that no longer halves the area only
    // costs time (the surgery copes with the rest).
    if (ratio < 1e-3 && ratio > 0.5 * previous) break;
  }
  };
#ifdef SDM_HAVE_CHOLMOD
  if (opt.solver == SparseSolver::cholmod) {
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> solver;
    iterate(solver);
  } else
#endif
  if (opt.solver == SparseSolver::eigen) {
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
    iterate(solver);
  } else {
    SupernodalSolver solver;
    iterate(solver);
  }
  res.positions = V;
  return res;
}

bool sparse_solver_available(SparseSolver s) {
#ifdef SDM_HAVE_CHOLMOD
  (void)s;
  return true;
#else
  return s != SparseSolver::cholmod;
#endif
}

ContractResult contract_mesh(const Mesh& mesh, const ContractOptions& options, const Progress& progress) {
  return contract_mesh(vertex_matrix(mesh), face_matrix(mesh), options, progress);
}

}  // namespace sdm
