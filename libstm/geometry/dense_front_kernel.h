#pragma once
/// The bodies of factor_front, forward_front and backward_front (dense_front.h), compiled once per
/// instruction set: the including file names the namespace (SDM_DENSE_KERNEL_NS) and, for the AVX2
/// copy, renames Eigen's namespace before including this, so that no Eigen function compiled for
/// AVX2 can stand in for the baseline's at link time.
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace sdm::SDM_DENSE_KERNEL_NS {

/// Right-looking, four columns at a time: each panel of four is factorised (left-looking inside it),
/// then the columns right of it lose the panel's contribution in one pass (four multiply-adds per
/// element loaded), the last m - k columns thus becoming the update. On the fronts of the CGAL
/// meshes' contractions up to 96 rows this is 1.15-2 times faster than Eigen's blocked LLT, solve
/// and rank update (which pack their operands for each block of 8 columns); beyond, slower.
bool factor_front_panels(double* A, int m, int k, double* update) {
  constexpr int W = 4;
  for (int p = 0; p < k; p += W) {
    const int w = std::min(W, k - p);
    for (int c = p; c < p + w; ++c) {
      double* __restrict col = A + long(c) * m;
      for (int q = p; q < c; ++q) {
        const double* __restrict done = A + long(q) * m;
        const double a = done[c];
        for (int r = c; r < m; ++r) col[r] -= a * done[r];
      }
      if (!(col[c] > 0.0)) return false;
      const double d = std::sqrt(col[c]), inv = 1.0 / d;
      col[c] = d;
      for (int r = c + 1; r < m; ++r) col[r] *= inv;
    }
    const double* panel = A + long(p) * m;
    for (int s = p + w; s < m; ++s) {
      double* __restrict t = A + long(s) * m;
      if (w == W) {
        const double* __restrict p0 = panel;
        const double* __restrict p1 = panel + m;
        const double* __restrict p2 = panel + 2 * long(m);
        const double* __restrict p3 = panel + 3 * long(m);
        const double a0 = p0[s], a1 = p1[s], a2 = p2[s], a3 = p3[s];
        for (int r = s; r < m; ++r) t[r] = t[r] - a0 * p0[r] - a1 * p1[r] - a2 * p2[r] - a3 * p3[r];
      } else {
        for (int q = 0; q < w; ++q) {
          const double* __restrict done = panel + long(q) * m;
          const double a = done[s];
          for (int r = s; r < m; ++r) t[r] -= a * done[r];
        }
      }
    }
  }
  const int n = m - k;
  for (int j = 0; j < n; ++j)
    std::copy(A + long(k + j) * m + k + j, A + long(k + j) * m + m, update + long(j) * n + j);
  return true;
}

bool factor_front(double* front_data, int m, int k, double* update_data) {
  if (m <= 96) return factor_front_panels(front_data, m, k, update_data);
  Eigen::Map<Eigen::MatrixXd> front(front_data, m, m);
  Eigen::Ref<Eigen::MatrixXd> diag = front.topLeftCorner(k, k);
  const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(diag);
  if (llt.info() != Eigen::Success) return false;
  if (m > k) {
    auto below = front.bottomLeftCorner(m - k, k);
    diag.triangularView<Eigen::Lower>().transpose().template solveInPlace<Eigen::OnTheRight>(below);
    Eigen::Map<Eigen::MatrixXd> update(update_data, m - k, m - k);
    update.triangularView<Eigen::Lower>() = front.bottomRightCorner(m - k, m - k);
    update.selfadjointView<Eigen::Lower>().rankUpdate(below, -1.0);
  }
  return true;
}

/// Level-1 loops over L's columns (each read once, the three right-hand sides together): Eigen's
/// blocked triangular solve and product pack their operands first, which cost more than the
/// arithmetic on supernodes of a few columns and three right-hand sides.
void forward_front(const double* L, int m, int k, double* ys, long ldy, double* gathered) {
  using Vec = Eigen::Map<Eigen::VectorXd>;
  using ConstVec = Eigen::Map<const Eigen::VectorXd>;
  const int below = m - k;
  for (int j = 0; j < 3; ++j) Vec(gathered + long(j) * below, below).setZero();
  for (int c = 0; c < k; ++c) {
    const double* col = L + long(c) * m;
    const ConstVec inside(col + c + 1, k - c - 1), under(col + k, below);
    for (int j = 0; j < 3; ++j) {
      double* y = ys + j * ldy;
      const double v = y[c] / col[c];
      y[c] = v;
      Vec(y + c + 1, k - c - 1) -= v * inside;
      Vec(gathered + long(j) * below, below) += v * under;
    }
  }
}

void backward_front(const double* L, int m, int k, double* ys, long ldy, const double* gathered) {
  using ConstVec = Eigen::Map<const Eigen::VectorXd>;
  const int below = m - k;
  for (int c = k - 1; c >= 0; --c) {
    const double* col = L + long(c) * m;
    const ConstVec inside(col + c + 1, k - c - 1), under(col + k, below);
    for (int j = 0; j < 3; ++j) {
      double* y = ys + j * ldy;
      const double rest = inside.dot(ConstVec(y + c + 1, k - c - 1)) + under.dot(ConstVec(gathered + long(j) * below, below));
      y[c] = (y[c] - rest) / col[c];
    }
  }
}

}  // namespace sdm::SDM_DENSE_KERNEL_NS
