#include "libstm/skeleton/contract_mesh.h"

#include "libstm/core/errors.h"
#include "libstm/core/stopwatch.h"
#include "libstm/geometry/differential_geometry.h"
#include "libstm/geometry/supernodal_cholesky.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#ifdef SDM_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace sdm {

namespace {

// Cotangent of the angle between u and v, clamped: contracted triangles degenerate, and an
// unbounded weight would make the system singular.
double clamped_cot(const Eigen::Vector3d& u, const Eigen::Vector3d& v, double lo, double hi) {
  const double c = u.dot(v);
  const double s = u.cross(v).norm();
  if (s <= std::abs(c) / hi) return c >= 0 ? hi : lo;
  return std::clamp(c / s, lo, hi);
}

// Au et al.'s iteration on one mesh. The normal equations (L^T W_L^2 L + W_H^2) V' = W_H^2 V have
// the sparsity of pairs of vertices in one closed one-ring, whatever the weights: the pattern, and
// where each Laplacian entry lands in it, are set up once.
class Contraction {
 public:
  Contraction(const Eigen::MatrixX3d& V0, const Eigen::MatrixX3i& F, const ContractOptions& opt, const Progress& progress);
  // Iterates until the area ratio, the iteration count or stagnation stops it, or the solver fails
  // (the last good shape is kept).
  template <class Solver>
  void run(Solver& solver);
  ContractResult result() {
    res_.positions = V_;
    return std::move(res_);
  }

 private:
  int slot_in(int i, int j) const {
    return int(std::lower_bound(ring_[i].begin(), ring_[i].end(), j) - ring_[i].begin());
  }
  void build_rings();
  void build_pattern();
  double areas(std::vector<double>& vertex_area) const;
  void assemble_laplacian();
  Eigen::MatrixX3d assemble_system();
  void eliminate_pinned(Eigen::MatrixX3d& rhs);
  template <class Solver>
  bool solve(Solver& solver, const Eigen::MatrixX3d& rhs);
  void update_weights();

  const Eigen::MatrixX3i& F_;
  const ContractOptions& opt_;
  const Progress& progress_;
  const int n_, m_;
  ContractResult res_;
  Eigen::MatrixX3d V_;
  // Closed one-rings R_i = {i} + neighbours, sorted: row i of L lives on R_i.
  std::vector<std::vector<int>> ring_;
  // For every face edge (opposite corner k): where each end sits in the other's ring.
  std::vector<std::array<int, 6>> face_slots_;
  Eigen::SparseMatrix<double> A_;  // lower triangle of the normal equations' matrix
  std::vector<int> pair_slot_;     // value slot in A_ of every ring pair, ring by ring
  std::vector<int> diag_slot_;
  std::vector<std::vector<double>> lrow_;  // row i of L on R_i
  std::vector<double> va0_, va_;           // one-ring areas: original, current
  double area0_ = 0, ratio_ = 1.0;
  double WL0_ = 0, WL_ = 0;
  Eigen::VectorXd WH_;
  std::vector<char> pinned_;
  int npinned_ = 0;
  bool analysed_ = false;
};

Contraction::Contraction(const Eigen::MatrixX3d& V0, const Eigen::MatrixX3i& F, const ContractOptions& opt,
                         const Progress& progress)
    : F_(F), opt_(opt), progress_(progress), n_(int(V0.rows())), m_(int(F.rows())), V_(V0) {
  build_rings();
  build_pattern();
  area0_ = areas(va0_);
  if (!(area0_ > 0)) throw InputError("cannot contract a mesh of zero area");
  WL0_ = opt.laplacian_weight * std::sqrt(double(m_));
  WL_ = WL0_;
  WH_ = Eigen::VectorXd::Ones(n_);
  lrow_.resize(n_);
  for (int i = 0; i < n_; ++i) lrow_[i].assign(ring_[i].size(), 0.0);
  pinned_.assign(n_, 0);
}

void Contraction::build_rings() {
  std::vector<int> corners(n_, 1);
  for (int f = 0; f < m_; ++f)
    for (int k = 0; k < 3; ++k) corners[F_(f, k)] += 2;
  ring_.resize(n_);
  for (int i = 0; i < n_; ++i) ring_[i].reserve(corners[i]), ring_[i].push_back(i);
  for (int f = 0; f < m_; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F_(f, k), b = F_(f, (k + 1) % 3);
      ring_[a].push_back(b), ring_[b].push_back(a);
    }
  for (auto& r : ring_) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  }
  face_slots_.resize(m_);
  for (int f = 0; f < m_; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F_(f, (k + 1) % 3), b = F_(f, (k + 2) % 3);
      face_slots_[f][2 * k] = slot_in(a, b);
      face_slots_[f][2 * k + 1] = slot_in(b, a);
    }
}

// Pattern of the lower triangle of L^T L (+ diagonal): every pair inside one closed ring; and the
// value slot of every ring pair, so each iteration fills A without searching. Column j's rows are
// the vertices i >= j of the rings j is in, which are the rings of j's own closed ring.
void Contraction::build_pattern() {
  std::vector<int> start(n_ + 1, 0), rows;
  rows.reserve(size_t(n_) * 16);
  // A row met again in another ring is skipped by its mark, so only the distinct rows are sorted
  // (sorting every ring's rows with their repeats was most of the set-up).
  std::vector<int> mark(n_, -1);
  for (int j = 0; j < n_; ++j) {
    const size_t first = rows.size();
    for (int k : ring_[j])
      for (auto it = std::lower_bound(ring_[k].begin(), ring_[k].end(), j); it != ring_[k].end(); ++it)
        if (mark[*it] != j) mark[*it] = j, rows.push_back(*it);
    std::sort(rows.begin() + first, rows.end());
    start[j + 1] = int(rows.size());
  }
  A_ = Eigen::SparseMatrix<double>(n_, n_);
  A_.resizeNonZeros(Eigen::Index(rows.size()));
  std::copy(start.begin(), start.end(), A_.outerIndexPtr());
  std::copy(rows.begin(), rows.end(), A_.innerIndexPtr());
  std::fill(A_.valuePtr(), A_.valuePtr() + rows.size(), 0.0);
  size_t pairs = 0;
  for (const auto& r : ring_) pairs += r.size() * (r.size() + 1) / 2;
  pair_slot_.reserve(pairs);
  // A ring's rows r[b] <= r[a] <= ... all lie in column r[b] (sorted): one cursor per b walks down
  // that column as a grows, instead of a binary search per pair (the set-up was a tenth of a small
  // mesh's contraction).
  const int* row_of = A_.innerIndexPtr();
  std::vector<int> cursor;
  for (const auto& r : ring_) {
    cursor.resize(r.size());
    for (size_t a = 0; a < r.size(); ++a) {
      cursor[a] = A_.outerIndexPtr()[r[a]];
      for (size_t b = 0; b <= a; ++b) {
        int& q = cursor[b];
        while (row_of[q] < r[a]) ++q;
        pair_slot_.push_back(q);
      }
    }
  }
  diag_slot_.resize(n_);
  for (int i = 0; i < n_; ++i) diag_slot_[i] = A_.outerIndexPtr()[i];  // the diagonal heads its column
}

// Total area of the current shape; the area of each vertex's faces into vertex_area.
double Contraction::areas(std::vector<double>& vertex_area) const {
  vertex_area.assign(n_, 0.0);
  double total = 0;
  for (int f = 0; f < m_; ++f) {
    const Eigen::Vector3d a = V_.row(F_(f, 0)), b = V_.row(F_(f, 1)), c = V_.row(F_(f, 2));
    const double fa = triangle_area(a, b, c);
    total += fa;
    for (int k = 0; k < 3; ++k) vertex_area[F_(f, k)] += fa;
  }
  return total;
}

// Laplacian of the current shape (uniform weights count each face corner 1/2, so that an
// interior edge weighs 1 like the cotangent weights of an equilateral mesh).
void Contraction::assemble_laplacian() {
  for (auto& r : lrow_) std::fill(r.begin(), r.end(), 0.0);
  for (int f = 0; f < m_; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int c = F_(f, k), a = F_(f, (k + 1) % 3), b = F_(f, (k + 2) % 3);
      const double w = opt_.cotangent
                           ? clamped_cot(V_.row(a) - V_.row(c), V_.row(b) - V_.row(c), opt_.cot_min, opt_.cot_max) + 0.5 * opt_.uniform_blend
                           : 0.5;
      lrow_[a][face_slots_[f][2 * k]] += w;
      lrow_[b][face_slots_[f][2 * k + 1]] += w;
    }
  }
  for (int i = 0; i < n_; ++i) {
    double s = 0;
    const int self = slot_in(i, i);
    for (size_t a = 0; a < ring_[i].size(); ++a)
      if (int(a) != self) s += lrow_[i][a];
    lrow_[i][self] = -s;
  }
}

// A = W_L^2 L^T L + W_H^2 and its right-hand side W_H^2 V, pinned vertices eliminated.
Eigen::MatrixX3d Contraction::assemble_system() {
  double* val = A_.valuePtr();
  std::fill(val, val + A_.nonZeros(), 0.0);
  const double wl2 = WL_ * WL_;
  size_t p = 0;
  for (int i = 0; i < n_; ++i) {
    const auto& l = lrow_[i];
    if (pinned_[i]) {  // a collapsed one-ring's cotangents are noise; its row would fling its neighbours
      p += l.size() * (l.size() + 1) / 2;
      continue;
    }
    for (size_t a = 0; a < l.size(); ++a) {
      const double la = wl2 * l[a];
      for (size_t b = 0; b <= a; ++b) val[pair_slot_[p++]] += la * l[b];
    }
  }
  for (int i = 0; i < n_; ++i) val[diag_slot_[i]] += WH_[i] * WH_[i];
  Eigen::MatrixX3d rhs = WH_.cwiseAbs2().asDiagonal() * V_;
  if (npinned_) eliminate_pinned(rhs);
  return rhs;
}

// Pinned vertices are eliminated (their rows become identity) rather than weighted: with
// W_L growing geometrically, no finite W_H would keep them in place.
void Contraction::eliminate_pinned(Eigen::MatrixX3d& rhs) {
  double* val = A_.valuePtr();
  for (int col = 0; col < n_; ++col)
    for (int q = A_.outerIndexPtr()[col]; q < A_.outerIndexPtr()[col + 1]; ++q) {
      const int row = A_.innerIndexPtr()[q];
      if (!pinned_[row] && !pinned_[col]) continue;
      if (row == col) {
        val[q] = 1.0;
        continue;
      }
      if (!pinned_[row]) rhs.row(row) -= val[q] * V_.row(col);
      if (!pinned_[col]) rhs.row(col) -= val[q] * V_.row(row);
      val[q] = 0.0;
    }
  for (int i = 0; i < n_; ++i)
    if (pinned_[i]) rhs.row(i) = V_.row(i);
}

// Factorises A (same pattern every iteration: one analysis) and solves; false, keeping the last
// good shape, when the factorisation fails or the solution is not finite.
template <class Solver>
bool Contraction::solve(Solver& solver, const Eigen::MatrixX3d& rhs) {
  const Stopwatch factor_time;
  if (!analysed_) solver.analyzePattern(A_), analysed_ = true;
  solver.factorize(A_);
  res_.factor_seconds += factor_time.seconds();
  if (solver.info() != Eigen::Success) return false;
  Eigen::MatrixX3d Vn = solver.solve(rhs);
  if (!Vn.allFinite()) return false;
  V_ = Vn;
  return true;
}

// Au et al.: W_H,i = sqrt(A_i^0 / A_i^t); a collapsed one-ring is pinned where it is. W_L grows
// by s_L up to its cap.
void Contraction::update_weights() {
  for (int i = 0; i < n_; ++i) {
    const double r = va_[i] / va0_[i];
    if (r < opt_.pin_area_ratio && !pinned_[i]) pinned_[i] = 1, ++npinned_;
    WH_[i] = pinned_[i] ? 1.0 : std::sqrt(1.0 / r);
  }
  WL_ = std::min(WL_ * opt_.laplacian_scale, WL0_ * opt_.max_laplacian_growth);
}

template <class Solver>
void Contraction::run(Solver& solver) {
  for (int it = 0; it < opt_.max_iterations && ratio_ > opt_.area_ratio_stop; ++it) {
    assemble_laplacian();
    if (!solve(solver, assemble_system())) break;
    const double area = areas(va_);
    const double previous = ratio_;
    ratio_ = area / area0_;
    res_.area_ratio.push_back(ratio_);
    res_.iterations = it + 1;
    if (progress_) {
      char line[160];
      std::snprintf(line, sizeof line, "contraction iteration %d: area ratio %.3g, W_L %.3g, pinned %d", it + 1, ratio_,
                    WL_, npinned_);
      progress_(line);
    }
    update_weights();
    // Stagnation: once the shape is thin, an iteration that no longer halves the area only
    // costs time (the surgery copes with the rest).
    if (opt_.stop_when_stagnant && ratio_ < opt_.stagnant_below && ratio_ > 0.5 * previous) break;
  }
}

}  // namespace

ContractResult contract_mesh(const Eigen::MatrixX3d& V0, const Eigen::MatrixX3i& F, const ContractOptions& opt,
                             const Progress& progress) {
  if (V0.rows() == 0 || F.rows() == 0) {
    ContractResult res;
    res.positions = V0;
    return res;
  }
  Contraction contraction(V0, F, opt, progress);
#ifdef SDM_HAVE_CHOLMOD
  if (opt.solver == SparseSolver::cholmod) {
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> solver;
    contraction.run(solver);
  } else
#endif
  if (opt.solver == SparseSolver::eigen) {
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
    contraction.run(solver);
  } else {
    SupernodalSolver solver;
    contraction.run(solver);
  }
  return contraction.result();
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
