#include "libstm/skeleton/medial_poles.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace sdm {

MedialPoles::MedialPoles(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const TriangleBvh* surface)
    : V_(V), own_(surface ? TriangleBvh() : TriangleBvh(V, F, {}, 8)), bvh_(surface ? surface : &own_) {
  const int n = int(V.rows());
  N_ = Eigen::MatrixX3d::Zero(n, 3);
  double volume = 0;
  reach_.assign(n, 0.0);
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::Vector3d w = (b - a).cross(c - a);  // area-weighted normal
    volume += a.dot(b.cross(c));
    for (int k = 0; k < 3; ++k) {
      N_.row(F(f, k)) += w;
      const double e = (V.row(F(f, k)) - V.row(F(f, (k + 1) % 3))).norm();
      reach_[F(f, k)] = std::max(reach_[F(f, k)], e);
      reach_[F(f, (k + 1) % 3)] = std::max(reach_[F(f, (k + 1) % 3)], e);
    }
  }
  inward_ = volume >= 0 ? -1.0 : 1.0;
  const double diag = n ? (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm() : 0.0;
  r_max_ = 0.5 * diag, eps_ = 1e-9 * diag;
}

Eigen::Vector3d MedialPoles::pole(int i) const {
  const Eigen::Vector3d p = V_.row(i);
  const double len = N_.row(i).norm();
  if (!(len > 0)) return p;
  const Eigen::Vector3d m = inward_ * N_.row(i).transpose() / len;
  // Shrink a ball tangent at p until the surface point nearest its centre is p itself: each
  // step takes the ball through p and that nearest point.
  // No ball tangent at p is wider than the chord along the inward normal: start from half of it.
  const auto hit = bvh_->first_hit(p, m, eps_);
  double r = hit.face >= 0 ? std::min(r_max_, 0.5 * hit.t) : r_max_;
  for (int it = 0; it < 50; ++it) {
    const Eigen::Vector3d c = p + r * m;
    const auto q = bvh_->closest_point(c, r - eps_);
    if (q.face < 0) break;  // the ball is empty
    const Eigen::Vector3d d = q.point - p;
    // The nearest point lies next to p: the vertex normal is not the normal of the faces around
    // it, and following that point would shrink the ball to nothing.
    if (d.norm() < 2.0 * reach_[i]) break;
    const double along = m.dot(d);
    if (!(along > 0)) break;
    const double r_new = d.squaredNorm() / (2.0 * along);
    if (!(r_new < r - eps_)) break;
    r = r_new;
  }
  return p + r * m;
}

Eigen::MatrixX3d medial_poles(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  const MedialPoles poles(V, F);
  Eigen::MatrixX3d P(V.rows(), 3);
  for (int i = 0; i < poles.size(); ++i) P.row(i) = poles.pole(i);
  return P;
}

Eigen::MatrixX3d smooth_poles(const Eigen::MatrixX3d& poles, const Eigen::MatrixX3i& F, int steps) {
  Eigen::MatrixX3d smooth = poles;
  std::vector<std::vector<int>> nb(poles.rows());
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) nb[F(f, k)].push_back(F(f, (k + 1) % 3)), nb[F(f, (k + 1) % 3)].push_back(F(f, k));
  for (int step = 0; step < steps; ++step) {
    Eigen::MatrixX3d next = smooth;
    for (int i = 0; i < poles.rows(); ++i) {
      if (nb[i].empty()) continue;
      Eigen::RowVector3d c = Eigen::RowVector3d::Zero();
      for (int j : nb[i]) c += smooth.row(j);
      next.row(i) = 0.5 * smooth.row(i) + 0.5 * c / double(nb[i].size());
    }
    smooth = std::move(next);
  }
  return smooth;
}

}  // namespace sdm
