#include "libstm/registration/discrete_map_energy.h"

#include "libstm/core/errors.h"

#include <cmath>
#include <vector>

namespace sdm {

DiscreteMapRows discrete_map_rows(const FloatRows& phi_q, const Eigen::VectorXf& lambda_q, const FloatRows& phi_d,
                                  const Eigen::VectorXf& lambda_d, const Eigen::MatrixXf& c_qd, const Eigen::MatrixXf& c_dq,
                                  const DiscreteMapWeights& w) {
  const Eigen::Index k = phi_q.cols();
  if (phi_d.cols() != k || lambda_q.size() != k || lambda_d.size() != k || c_qd.rows() != k || c_qd.cols() != k || c_dq.rows() != k ||
      c_dq.cols() != k)
    throw InputError("discrete_map_rows: the functions, eigenvalues and functional maps need k = " + std::to_string(k) + " each");
  // One block per term with a weight: (weight, query block, database block).
  struct Block {
    float w;
    FloatRows q, d;
  };
  std::vector<Block> blocks;
  const auto add = [&](double weight, FloatRows q, FloatRows d) {
    if (weight > 0) blocks.push_back({float(std::sqrt(weight)), std::move(q), std::move(d)});
  };
  add(w.properness, phi_q * c_qd, phi_d);
  if (w.bijectivity > 0) add(w.bijectivity, phi_q, phi_d * c_dq);
  if (w.orthogonality > 0) add(w.orthogonality, phi_q, phi_d * c_qd.transpose());
  if (w.commutativity > 0) {
    const float scale = lambda_d[k - 1] > 0 ? lambda_d[k - 1] : 1.0f;
    const Eigen::VectorXf lq = lambda_q / scale, ld = lambda_d / scale;
    add(w.commutativity, phi_q * (lq.asDiagonal() * c_qd), phi_d * ld.asDiagonal());
  }
  DiscreteMapRows rows{FloatRows(phi_q.rows(), Eigen::Index(blocks.size()) * k), FloatRows(phi_d.rows(), Eigen::Index(blocks.size()) * k)};
  for (size_t b = 0; b < blocks.size(); ++b) {
    rows.queries.middleCols(Eigen::Index(b) * k, k) = blocks[b].w * blocks[b].q;
    rows.database.middleCols(Eigen::Index(b) * k, k) = blocks[b].w * blocks[b].d;
  }
  return rows;
}

}  // namespace sdm
