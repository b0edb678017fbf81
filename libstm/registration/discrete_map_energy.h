#pragma once
/// The pointwise-map step of the discrete solver of Ren, Melzi, Wonka and Ovsjanikov 2021
/// ("Discrete optimization for shape matching", SGP, Section 4). Mapping each vertex of a shape Q
/// onto a shape D (Pi: Q's vertices to D's, C_qd = Phi_Q^+ Pi Phi_D the functional map from D's
/// functions to Q's, C_dq the other way), each term of their energy, with the functional maps held,
/// is a distance between a row of Q and a row of D:
///   properness     Pi Phi_D       ~ Phi_Q C_qd
///   bijectivity    Pi Phi_D C_dq  ~ Phi_Q         (C_qd C_dq = I)
///   orthogonality  Pi Phi_D C_qd^T ~ Phi_Q        (C_qd C_qd^T = I)
///   commutativity  Pi Phi_D Lam_D ~ Phi_Q Lam_Q C_qd  (C_qd Lam_D = Lam_Q C_qd)
/// so the weighted sum is minimised by one nearest-neighbour search between the stacked rows
/// (each block times the square root of its weight). Used inside the spectral refinement
/// (libstm/registration/zoomout.h, ZoomOutOptions::bijectivity_weight and the two beside it).
#include <Eigen/Dense>

namespace sdm {

using FloatRows = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The weights of the energy's terms (a term at 0 adds no columns).
struct DiscreteMapWeights {
  double properness = 1, bijectivity = 0, orthogonality = 0, commutativity = 0;
};

/// Per vertex of Q a query row and per vertex of D a database row, as many columns each.
struct DiscreteMapRows {
  FloatRows queries, database;
};

/// The stacked rows for mapping Q onto D. `phi_q` (n_q x k) and `phi_d` (n_d x k): the first k
/// eigenfunctions of each shape at unit area; `lambda_q`, `lambda_d`: their k eigenvalues at unit
/// area (divided here by lambda_d's last, so that the commutativity block weighs like the others);
/// `c_qd`, `c_dq`: k x k as above.
/// \throw InputError when the sizes disagree.
DiscreteMapRows discrete_map_rows(const FloatRows& phi_q, const Eigen::VectorXf& lambda_q, const FloatRows& phi_d,
                                  const Eigen::VectorXf& lambda_d, const Eigen::MatrixXf& c_qd, const Eigen::MatrixXf& c_dq,
                                  const DiscreteMapWeights& weights);

}  // namespace sdm
