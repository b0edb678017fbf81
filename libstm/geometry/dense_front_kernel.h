#pragma once
// The body of factor_front (dense_front.h), compiled once per instruction set: the including file
// names the namespace (SDM_DENSE_KERNEL_NS) and, for the AVX2 copy, renames Eigen's namespace before
// including this, so that no Eigen function compiled for AVX2 can stand in for the baseline's at
// link time.
#include <Eigen/Dense>

namespace sdm::SDM_DENSE_KERNEL_NS {

bool factor_front(double* front_data, int m, int k, double* update_data) {
  Eigen::Map<Eigen::MatrixXd> front(front_data, m, m);
  Eigen::Ref<Eigen::MatrixXd> diag = front.topLeftCorner(k, k);
  const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(diag);
  if (llt.info() != Eigen::Success) return false;
  if (m > k) {
    auto below = front.bottomLeftCorner(m - k, k);
    diag.triangularView<Eigen::Lower>().transpose().template solveInPlace<Eigen::OnTheRight>(below);
    Eigen::Map<Eigen::MatrixXd> update(update_data, m - k, m - k);
    update = front.bottomRightCorner(m - k, m - k);
    update.selfadjointView<Eigen::Lower>().rankUpdate(below, -1.0);
  }
  return true;
}

}  // namespace sdm::SDM_DENSE_KERNEL_NS
