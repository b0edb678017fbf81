#include "libstm/geometry/differential_geometry.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace sdm {

Eigen::Vector3d barycentric(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c) {
  const Eigen::Vector3d e0 = b - a, e1 = c - a, d = p - a;
  const double d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1), d20 = d.dot(e0), d21 = d.dot(e1);
  const double den = d00 * d11 - d01 * d01;
  if (!(std::abs(den) > 1e-300)) return {1, 0, 0};
  const double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
  return {1 - v - w, v, w};
}

double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double* t) {
  const Eigen::Vector3d ab = b - a;
  const double l2 = ab.squaredNorm();
  const double tt = l2 > 0 ? (p - a).dot(ab) / l2 : 0.0;
  if (t) *t = tt;
  const double c = std::clamp(tt, 0.0, 1.0);
  return (p - (a + c * ab)).norm();
}

Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& M, double* trace, double* second_singular) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d d(1, 1, 1);
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) d(2) = -1;
  if (trace) *trace = svd.singularValues().cwiseProduct(d).sum();
  if (second_singular) *second_singular = svd.singularValues()(1) / std::max(1e-300, svd.singularValues()(0));
  // Assigned, not constructed: Eigen evaluates the assignment through a temporary (aliasing-safe
  // path), whose rounding the registrations were tuned and their tests measured with.
  Eigen::Matrix3d R;
  R = svd.matrixU() * d.asDiagonal() * svd.matrixV().transpose();
  return R;
}

Similarity Similarity::inverse() const {
  Similarity r;
  r.scale = 1.0 / scale;
  r.rotation = rotation.transpose();
  r.translation = -(r.scale * (r.rotation * translation));
  return r;
}

Similarity fit_similarity(const std::vector<Eigen::Vector3d>& x, const std::vector<Eigen::Vector3d>& y,
                          const std::vector<double>& w) {
  double W = 0;
  Eigen::Vector3d mx = Eigen::Vector3d::Zero(), my = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < x.size(); ++i) W += w[i], mx += w[i] * x[i], my += w[i] * y[i];
  Similarity T;
  if (!(W > 0)) return T;
  mx /= W, my /= W;
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  double var_x = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    S += w[i] * (y[i] - my) * (x[i] - mx).transpose();
    var_x += w[i] * (x[i] - mx).squaredNorm();
  }
  S /= W, var_x /= W;
  double trace = 0;
  T.rotation = nearest_rotation(S, &trace);
  T.scale = var_x > 0 ? trace / var_x : 1.0;
  if (!(T.scale > 0)) T.scale = 1;
  T.translation = my - T.scale * (T.rotation * mx);
  return T;
}

double weighted_quantile(const std::vector<double>& d, const std::vector<double>& w, double q) {
  std::vector<size_t> order(d.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return d[a] < d[b] || (d[a] == d[b] && a < b); });
  const double total = std::accumulate(w.begin(), w.end(), 0.0);
  double acc = 0;
  for (size_t i : order) {
    acc += w[i];
    if (acc >= q * total) return d[i];
  }
  return order.empty() ? 0.0 : d[order.back()];
}

}  // namespace sdm
