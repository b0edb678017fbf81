#include "libstm/skeleton/contract_points.h"

#include "libstm/core/errors.h"
#include "libstm/core/parallel.h"
#include "libstm/core/stopwatch.h"
#include "libstm/geometry/local_delaunay.h"
#include "libstm/geometry/point_kdtree.h"
#include "libstm/geometry/supernodal_cholesky.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#ifdef SDM_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif
#include <algorithm>
#include <cstdio>

namespace sdm {

namespace {

// Cotangent of the angle between u and v, clamped to [0, hi]: contracted triangles degenerate.
double clamped_cot(const Eigen::Vector3d& u, const Eigen::Vector3d& v, double hi) {
  const double c = u.dot(v), s = u.cross(v).norm();
  if (s <= std::abs(c) / hi) return c >= 0 ? hi : 0.0;
  return std::clamp(c / s, 0.0, hi);
}

// The Laplacian of the local triangles at positions P: per triangle (i, a, b), the edge i-a weighs
// the clamped cotangent at b plus `blend` (a uniform part, as proxy_contraction adds), i-b the one
// at a. A point without triangles gets uniform weights on its ring.
Eigen::SparseMatrix<double> local_laplacian(const Eigen::MatrixX3d& P, const LocalRings& lr, const PointContractOptions& opt) {
  const int n = int(P.rows());
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    double sum = 0;
    auto add = [&](int j, double w) { t.emplace_back(i, j, w), sum += w; };
    const Eigen::Vector3d p = P.row(i);
    for (const auto& [a, b] : lr.triangles[size_t(i)]) {
      const Eigen::Vector3d pa = P.row(a), pb = P.row(b);
      add(a, clamped_cot(p - pb, pa - pb, opt.cot_max) + opt.uniform_blend);
      add(b, clamped_cot(p - pa, pb - pa, opt.cot_max) + opt.uniform_blend);
    }
    if (lr.triangles[size_t(i)].empty())
      for (int j : lr.ring[size_t(i)]) add(j, 1.0);
    t.emplace_back(i, i, -sum);
  }
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(t.begin(), t.end());
  return L;
}

// The area of each point's local triangles at positions P (Au et al.'s one-ring area).
std::vector<double> ring_areas(const Eigen::MatrixX3d& P, const LocalRings& lr) {
  std::vector<double> area(lr.triangles.size(), 0.0);
  for (size_t i = 0; i < area.size(); ++i)
    for (const auto& [a, b] : lr.triangles[i])
      area[i] += 0.5 * (P.row(a) - P.row(Eigen::Index(i))).cross(P.row(b) - P.row(Eigen::Index(i))).norm();
  return area;
}

double total(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s;
}

template <class Solver>
void iterate(Solver& solver, const LocalRings& lr, const std::vector<Eigen::Vector3d>& points, const PointContractOptions& opt,
             const Progress& progress, PointContractResult& res) {
  const int n = int(points.size());
  Eigen::MatrixX3d P(n, 3);
  for (int i = 0; i < n; ++i) P.row(i) = points[size_t(i)].transpose();
  const std::vector<double> a0 = ring_areas(P, lr);
  const double total0 = total(a0);
  Eigen::VectorXd WH = Eigen::VectorXd::Ones(n);
  const double WL0 = opt.laplacian_weight * std::sqrt(double(n));
  double WL = WL0, ratio = 1;
  for (int it = 0; it < opt.max_iterations && ratio > opt.area_ratio_stop; ++it) {
    const Eigen::SparseMatrix<double> L = local_laplacian(P, lr, opt);
    Eigen::SparseMatrix<double> D(n, n);
    D.setIdentity();
    D = WH.cwiseAbs2().asDiagonal() * D;
    Eigen::SparseMatrix<double> A = Eigen::SparseMatrix<double>(WL * WL * (L.transpose() * L) + D).triangularView<Eigen::Lower>();
    A.makeCompressed();
    const Stopwatch factor_time;
    solver.analyzePattern(A);
    solver.factorize(A);
    res.factor_seconds += factor_time.seconds();
    if (solver.info() != Eigen::Success) break;
    const Eigen::MatrixX3d next = solver.solve(WH.cwiseAbs2().asDiagonal() * P);
    if (!next.allFinite()) break;
    P = next;
    const std::vector<double> a = ring_areas(P, lr);
    const double previous = ratio;
    ratio = total0 > 0 ? total(a) / total0 : 0;
    res.area_ratio.push_back(ratio);
    res.iterations = it + 1;
    if (progress) {
      char line[160];
      std::snprintf(line, sizeof line, "point contraction iteration %d: area ratio %.3g, W_L %.3g", it + 1, ratio, WL);
      progress(line);
    }
    for (int i = 0; i < n; ++i)
      WH[i] = a0[size_t(i)] <= 0 ? 1.0 : a[size_t(i)] > 0 ? std::min(std::sqrt(a0[size_t(i)] / a[size_t(i)]), opt.max_attraction) : opt.max_attraction;
    const double cap = WL0 * opt.max_laplacian_growth;
    if (WL >= cap && ratio > 0.5 * previous) break;  // stagnant at full weight: an iteration no longer halves the area
    WL = std::min(WL * opt.laplacian_scale, cap);
  }
  res.positions = P;
}

}  // namespace

PointContractResult contract_points(const std::vector<Eigen::Vector3d>& points, const PointContractOptions& opt,
                                    SparseSolver solver, const Progress& progress) {
  if (points.size() < 4) throw InputError("cannot contract fewer than four points");
  PointContractResult res;
  const LocalRings lr = local_delaunay_rings(points, std::max(opt.neighbours, 3));
  res.rings.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i)
    for (int j : lr.ring[i]) res.rings[i].push_back(j), res.rings[size_t(j)].push_back(int(i));
  for (auto& r : res.rings) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  }
#ifdef SDM_HAVE_CHOLMOD
  if (solver == SparseSolver::cholmod) {
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> s;
    iterate(s, lr, points, opt, progress, res);
    return res;
  }
#endif
  if (solver == SparseSolver::eigen) {
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> s;
    iterate(s, lr, points, opt, progress, res);
  } else {
    SupernodalSolver s;
    iterate(s, lr, points, opt, progress, res);
  }
  return res;
}

}  // namespace sdm
