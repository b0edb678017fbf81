#pragma once
/// Where a stage puts the origin for a model. Far from the origin for its size (a model moved by
/// 1e4 or 1e6 of its diagonal) the stages' numbers lose their digits: the contraction's solves and
/// the medial poles' signed volume (a star of hundreds of nodes instead of the model's skeleton), the
/// decimater's quadrics (their plane offsets cancel). Those stages work on the model moved by this
/// shift and give their results back in the input's frame (tests/test_far_from_origin.cpp).
///
/// The shift is the bounding box's centre rounded to a multiple of the power of two at or above the
/// box's diagonal, so that a model near the origin (its centre within half of that) keeps its
/// coordinates bit for bit (shift 0, the results unchanged), and a copy moved by a multiple of it
/// sees exactly the numbers of the model at the origin (the subtraction is exact that far out).
#include <Eigen/Dense>

#include <cmath>

namespace sdm {

inline Eigen::Vector3d working_origin(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const double diag = (hi - lo).norm();
  if (!(diag > 0) || !std::isfinite(diag) || !lo.allFinite() || !hi.allFinite()) return Eigen::Vector3d::Zero();
  const double step = std::exp2(std::ceil(std::log2(diag)));
  return ((0.5 * (lo + hi)) / step).array().round().matrix() * step;
}

}  // namespace sdm
