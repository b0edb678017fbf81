// The contraction's sparse Cholesky (SupernodalCholesky) against Eigen's simplicial LDL^T on the
// matrices the contraction factorises: a mesh's Laplacian normal matrix plus a diagonal, refactorised
// with new values on one analysis; and indefinite input refused.
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/primitives.h"
#include "libstm/geometry/dense_front.h"
#include "libstm/geometry/supernodal_cholesky.h"

#include <catch2/catch.hpp>

#include <Eigen/SparseCholesky>
#include <random>

namespace {

// W_L^2 L^T L + diag(h^2) for the uniform Laplacian L of the mesh (the contraction's system).
Eigen::SparseMatrix<double> contraction_matrix(const sdm::Mesh& m, double wl, const std::vector<double>& h) {
  const int n = int(m.n_vertices());
  std::vector<Eigen::Triplet<double>> t;
  for (auto v : m.vertices()) {
    double deg = 0;
    for (auto w : m.vv_range(v)) t.emplace_back(v.idx(), w.idx(), -1.0), ++deg;
    t.emplace_back(v.idx(), v.idx(), deg);
  }
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(t.begin(), t.end());
  Eigen::SparseMatrix<double> A = wl * wl * Eigen::SparseMatrix<double>(L.transpose() * L);
  for (int i = 0; i < n; ++i) A.coeffRef(i, i) += h[i] * h[i];
  A.makeCompressed();
  return A;
}

Eigen::SparseMatrix<double> lower(const Eigen::SparseMatrix<double>& A) {
  Eigen::SparseMatrix<double> Lo = A.triangularView<Eigen::Lower>();
  Lo.makeCompressed();
  return Lo;
}

}  // namespace

TEST_CASE("supernodal Cholesky solves the contraction's systems as Eigen does, refactorised on one analysis", "[supernodal_cholesky]") {
  const sdm::Mesh m = sdm::make_primitive("bottle");
  const int n = int(m.n_vertices());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(0.5, 3.0);
  sdm::SupernodalCholesky chol;
  bool analysed = false;
  for (double wl : {1e-3, 0.1, 10.0, 1e3}) {
    std::vector<double> h(n);
    for (double& x : h) x = U(rng);
    h[n / 2] = 1e6;  // a pinned vertex, as the contraction makes them
    const Eigen::SparseMatrix<double> A = contraction_matrix(m, wl, h);
    const Eigen::SparseMatrix<double> Lo = lower(A);
    if (!analysed) chol.analyze(Lo), analysed = true;
    REQUIRE(chol.factorize(Lo));
    Eigen::MatrixX3d B = Eigen::MatrixX3d::Random(n, 3);
    const Eigen::MatrixX3d X = chol.solve(B);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ref(A);
    REQUIRE(ref.info() == Eigen::Success);
    const Eigen::MatrixX3d Xr = ref.solve(B);
    INFO("W_L " << wl);
    CHECK((A * X - B).norm() <= 1e-10 * B.norm());
    CHECK((X - Xr).norm() <= 1e-8 * Xr.norm());
  }
}

TEST_CASE("supernodal Cholesky refuses a matrix that is not positive definite", "[supernodal_cholesky]") {
  const sdm::Mesh m = sdm::make_primitive("ypsilon");
  const int n = int(m.n_vertices());
  std::vector<double> h(n, 1.0);
  Eigen::SparseMatrix<double> A = contraction_matrix(m, 1.0, h);
  sdm::SupernodalCholesky chol;
  chol.analyze(lower(A));
  REQUIRE(chol.factorize(lower(A)));
  A.coeffRef(n - 1, n - 1) = -5.0;
  CHECK_FALSE(chol.factorize(lower(A)));
  A.coeffRef(n - 1, n - 1) = std::numeric_limits<double>::quiet_NaN();
  CHECK_FALSE(chol.factorize(lower(A)));
}

TEST_CASE("supernodal Cholesky on a block-diagonal matrix of two parts", "[supernodal_cholesky]") {
  // Two disconnected chains: an elimination forest, not a tree.
  const int n = 40;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 4.0);
    if (i + 1 < n && i != n / 2 - 1) t.emplace_back(i + 1, i, -1.0), t.emplace_back(i, i + 1, -1.0);
  }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  sdm::SupernodalCholesky chol;
  chol.analyze(lower(A));
  REQUIRE(chol.factorize(lower(A)));
  const Eigen::MatrixX3d B = Eigen::MatrixX3d::Random(n, 3);
  CHECK((A * chol.solve(B) - B).norm() <= 1e-12 * B.norm());
}

TEST_CASE("supernodal Cholesky on two threads gives one thread's factor bit for bit", "[supernodal_cholesky]") {
  // The bottle's system (1566 unknowns, about 1.2e7 operations) takes the two-thread plan; twice
  // the bottle side by side (a forest of two trees) as well.
  const sdm::Mesh m = sdm::make_primitive("bottle");
  const int n = int(m.n_vertices());
  std::vector<double> h(n);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(0.5, 3.0);
  for (double& x : h) x = U(rng);
  const Eigen::SparseMatrix<double> one = contraction_matrix(m, 10.0, h);
  Eigen::SparseMatrix<double> two_parts(2 * n, 2 * n);
  {
    std::vector<Eigen::Triplet<double>> t;
    for (int part = 0; part < 2; ++part)
      for (int j = 0; j < n; ++j)
        for (Eigen::SparseMatrix<double>::InnerIterator it(one, j); it; ++it)
          t.emplace_back(int(it.row()) + part * n, j + part * n, it.value() * (1.0 + part));
    two_parts.setFromTriplets(t.begin(), t.end());
    two_parts.makeCompressed();
  }
  const Eigen::SparseMatrix<double>& two = two_parts;
  for (const Eigen::SparseMatrix<double>* A : {&one, &two}) {
    const Eigen::SparseMatrix<double> Lo = lower(*A);
    const Eigen::MatrixX3d B = Eigen::MatrixX3d::Random(A->rows(), 3);
    sdm::SupernodalCholesky serial, parallel;
    serial.analyze(Lo, 1);
    parallel.analyze(Lo, 2);
    CHECK_FALSE(serial.two_threads());
    REQUIRE(parallel.two_threads());
    REQUIRE(serial.factorize(Lo));
    REQUIRE(parallel.factorize(Lo));
    const Eigen::MatrixX3d X = parallel.solve(B);
    CHECK((X - serial.solve(B)).cwiseAbs().maxCoeff() == 0.0);
    CHECK((*A * X - B).norm() <= 1e-10 * B.norm());
  }
  // A negative pivot anywhere, whichever thread meets it, fails the factorisation.
  Eigen::SparseMatrix<double> A = one;
  sdm::SupernodalCholesky chol;
  chol.analyze(lower(A), 2);
  for (int v : {0, n / 3, n / 2, n - 1}) {
    const double keep = A.coeff(v, v);
    A.coeffRef(v, v) = -1e9;
    INFO("vertex " << v);
    CHECK_FALSE(chol.factorize(lower(A)));
    A.coeffRef(v, v) = keep;
  }
  CHECK(chol.factorize(lower(A)));
}

TEST_CASE("the dense front kernels factorise as the definition says, on either instruction set", "[supernodal_cholesky]") {
  // Fronts of the sizes the contraction meets (k columns of m rows), from a random SPD matrix:
  // L11 L11^T = F11, L21 L11^T = F21, update = F22 - L21 L21^T, each to rounding; the AVX2 copy
  // (where this build and processor have it) agrees with the baseline to rounding too.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::vector<sdm::DenseKernels> kernels{sdm::DenseKernels::baseline};
  if (sdm::avx2_kernels_available()) kernels.push_back(sdm::DenseKernels::avx2);
  else WARN("this processor or build has no AVX2 kernels: only the baseline is checked");
  // Up to 96 rows the panel kernel runs, beyond it Eigen's blocked one: both sides of the switch,
  // widths that are and are not multiples of the panel's four columns.
  for (auto [m, k] : {std::pair{1, 1}, {7, 3}, {66, 57}, {96, 10}, {97, 90}, {100, 84}, {340, 282}}) {
    Eigen::MatrixXd G(m, m);
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) G(i, j) = U(rng);
    const Eigen::MatrixXd F = G * G.transpose() + m * Eigen::MatrixXd::Identity(m, m);
    std::vector<Eigen::MatrixXd> fronts, updates;
    for (sdm::DenseKernels which : kernels) {
      Eigen::MatrixXd front = F, update = Eigen::MatrixXd::Zero(m - k, m - k);
      front.triangularView<Eigen::StrictlyUpper>().setZero();  // only the lower triangle is read
      REQUIRE(sdm::factor_front(front.data(), m, k, update.data(), which));
      const Eigen::MatrixXd L11 = front.topLeftCorner(k, k).triangularView<Eigen::Lower>();
      const Eigen::MatrixXd L21 = front.bottomLeftCorner(m - k, k);
      const double scale = F.norm();
      INFO("m " << m << ", k " << k << ", kernels " << (which == sdm::DenseKernels::avx2 ? "avx2" : "baseline"));
      CHECK((L11 * L11.transpose() - F.topLeftCorner(k, k)).norm() <= 1e-13 * scale);
      CHECK((L21 * L11.transpose() - F.bottomLeftCorner(m - k, k)).norm() <= 1e-13 * scale);
      const Eigen::MatrixXd expected = F.bottomRightCorner(m - k, m - k) - L21 * L21.transpose();
      CHECK((Eigen::MatrixXd(update.triangularView<Eigen::Lower>()) - Eigen::MatrixXd(expected.triangularView<Eigen::Lower>())).norm() <=
            1e-13 * scale);
      fronts.push_back(front.leftCols(k));
      updates.push_back(update.triangularView<Eigen::Lower>());
    }
    if (fronts.size() == 2) {
      CHECK((fronts[0] - fronts[1]).norm() <= 1e-13 * fronts[0].norm());
      CHECK((updates[0] - updates[1]).norm() <= 1e-13 * (1 + updates[0].norm()));
    }
    // Not positive definite: refused by either kernel.
    for (sdm::DenseKernels which : kernels) {
      Eigen::MatrixXd front = F, update(m - k, m - k);
      front(k - 1, k - 1) = -1.0;
      CHECK_FALSE(sdm::factor_front(front.data(), m, k, update.data(), which));
    }
  }
}

TEST_CASE("the dense solve kernels undo a supernode's triangles, on either instruction set", "[supernodal_cholesky]") {
  // A supernode's block (L11 lower triangular with a positive diagonal on top of L21), its rows of
  // three right-hand sides inside a taller column-major array: forward_front leaves x with
  // L11 x = b and gathered = L21 x; backward_front leaves x with L11^T x = b - L21^T g.
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::vector<sdm::DenseKernels> kernels{sdm::DenseKernels::baseline};
  if (sdm::avx2_kernels_available()) kernels.push_back(sdm::DenseKernels::avx2);
  for (auto [m, k] : {std::pair{1, 1}, {5, 2}, {40, 40}, {97, 61}, {300, 150}}) {
    Eigen::MatrixXd L(m, k);
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < m; ++i) L(i, j) = i < j ? 0.0 : i == j ? 2.0 + U(rng) : U(rng) / std::sqrt(double(k));
    const int below = m - k, n = k + 11, first = 7;
    const Eigen::MatrixXd b = Eigen::MatrixXd::Random(k, 3), g = Eigen::MatrixXd::Random(below, 3);
    const Eigen::MatrixXd L11 = L.topRows(k), L21 = L.bottomRows(below);
    std::vector<Eigen::MatrixXd> results;
    for (sdm::DenseKernels which : kernels) {
      INFO("m " << m << ", k " << k << ", kernels " << (which == sdm::DenseKernels::avx2 ? "avx2" : "baseline"));
      Eigen::MatrixXd y = Eigen::MatrixXd::Constant(n, 3, 42.0);
      y.middleRows(first, k) = b;
      Eigen::MatrixXd gathered(below, 3);
      sdm::forward_front(L.data(), m, k, &y(first, 0), n, gathered.data(), which);
      const Eigen::MatrixXd x = y.middleRows(first, k);
      CHECK((L11 * x - b).norm() <= 1e-13 * b.norm());
      if (below > 0) CHECK((gathered - L21 * x).norm() <= 1e-13 * (1 + gathered.norm()));
      CHECK((y.topRows(first).array() == 42.0).all());  // rows outside the supernode untouched
      CHECK((y.bottomRows(n - first - k).array() == 42.0).all());
      y.middleRows(first, k) = b;
      sdm::backward_front(L.data(), m, k, &y(first, 0), n, g.data(), which);
      const Eigen::MatrixXd z = y.middleRows(first, k);
      CHECK((L11.transpose() * z - (b - L21.transpose() * g)).norm() <= 1e-13 * (b.norm() + g.norm()));
      results.push_back(x);
      results.push_back(z);
    }
    if (results.size() == 4) {
      CHECK((results[0] - results[2]).norm() <= 1e-13 * results[0].norm());
      CHECK((results[1] - results[3]).norm() <= 1e-13 * results[1].norm());
    }
  }
}
