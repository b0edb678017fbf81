// The discrete solver's pointwise-map step (libstm/registration/discrete_map_energy.h): the rows'
// distances are the terms of Ren et al. 2021's energy.
#include "libstm/core/errors.h"
#include "libstm/registration/discrete_map_energy.h"

#include <catch2/catch.hpp>

#include <random>

namespace {

sdm::FloatRows random_rows(Eigen::Index rows, Eigen::Index cols, std::mt19937& rng) {
  std::normal_distribution<float> n(0, 1);
  sdm::FloatRows m(rows, cols);
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = n(rng);
  return m;
}

}  // namespace

TEST_CASE("discrete_map_rows: the squared row distances of a map sum to its weighted energy", "[discrete_map_energy]") {
  std::mt19937 rng(3);
  const int k = 6, nq = 40, nd = 55;
  const sdm::FloatRows phi_q = random_rows(nq, k, rng), phi_d = random_rows(nd, k, rng);
  const Eigen::MatrixXf c_qd = random_rows(k, k, rng), c_dq = random_rows(k, k, rng);
  Eigen::VectorXf lambda_q(k), lambda_d(k);
  for (int i = 0; i < k; ++i) lambda_q[i] = float(i * i), lambda_d[i] = float(i * i) + 0.5f * float(i);
  const sdm::DiscreteMapWeights w{1, 0.5, 0.25, 2};
  const sdm::DiscreteMapRows rows = sdm::discrete_map_rows(phi_q, lambda_q, phi_d, lambda_d, c_qd, c_dq, w);
  REQUIRE(rows.queries.rows() == nq);
  REQUIRE(rows.database.rows() == nd);
  REQUIRE(rows.queries.cols() == 4 * k);
  REQUIRE(rows.database.cols() == 4 * k);
  // A map Pi (each vertex of Q to one of D) and its energy, term by term.
  std::uniform_int_distribution<int> pick(0, nd - 1);
  sdm::FloatRows pulled(nq, k);
  double rows_sum = 0;
  for (int q = 0; q < nq; ++q) {
    const int d = pick(rng);
    pulled.row(q) = phi_d.row(d);
    rows_sum += double((rows.queries.row(q) - rows.database.row(d)).squaredNorm());
  }
  const float s = lambda_d[k - 1];
  const Eigen::VectorXf lq = lambda_q / s, ld = lambda_d / s;
  const double energy = (phi_q * c_qd - pulled).squaredNorm() + 0.5 * (phi_q - pulled * c_dq).squaredNorm() +
                        0.25 * (phi_q - pulled * c_qd.transpose()).squaredNorm() +
                        2 * (phi_q * lq.asDiagonal() * c_qd - pulled * ld.asDiagonal()).squaredNorm();
  CHECK(rows_sum == Approx(energy).epsilon(1e-4));
  // Terms at 0 add no columns; properness alone is ZoomOut's rows.
  const sdm::DiscreteMapRows plain = sdm::discrete_map_rows(phi_q, lambda_q, phi_d, lambda_d, c_qd, c_dq, {});
  REQUIRE(plain.queries.cols() == k);
  CHECK((plain.queries - phi_q * c_qd).cwiseAbs().maxCoeff() < 1e-5f);
  CHECK((plain.database - phi_d).cwiseAbs().maxCoeff() == 0);
  CHECK_THROWS_AS(sdm::discrete_map_rows(phi_q, lambda_q.head(k - 1), phi_d, lambda_d, c_qd, c_dq, w), sdm::InputError);
}

TEST_CASE("discrete_map_rows: a shape onto its own vertices permuted, every vertex finds itself", "[discrete_map_energy]") {
  std::mt19937 rng(5);
  const int k = 8, n = 300;
  const sdm::FloatRows phi_d = random_rows(n, k, rng);
  std::vector<int> perm(n);
  for (int i = 0; i < n; ++i) perm[size_t(i)] = i;
  std::shuffle(perm.begin(), perm.end(), rng);
  sdm::FloatRows phi_q(n, k);
  for (int i = 0; i < n; ++i) phi_q.row(i) = phi_d.row(perm[size_t(i)]);
  // An orthogonal C (a rotation of the functions) on both sides: Q's functions are D's rotated.
  const Eigen::HouseholderQR<Eigen::MatrixXf> qr(Eigen::MatrixXf(random_rows(k, k, rng)));
  const Eigen::MatrixXf r = qr.householderQ();
  const sdm::FloatRows phi_q_rotated = phi_q * r.transpose();  // Phi_Q C_qd = Pi Phi_D with C_qd = r
  Eigen::VectorXf lambda(k);
  lambda.setConstant(1);  // one eigenspace: commutativity holds for any C
  const sdm::DiscreteMapRows rows = sdm::discrete_map_rows(phi_q_rotated, lambda, phi_d, lambda, r, r.transpose(), {1, 1, 1, 1});
  int found = 0;
  for (int q = 0; q < n; ++q) {
    Eigen::Index at;
    (rows.database.rowwise() - rows.queries.row(q)).rowwise().squaredNorm().minCoeff(&at);
    found += int(at) == perm[size_t(q)] ? 1 : 0;
  }
  CHECK(found == n);
}
