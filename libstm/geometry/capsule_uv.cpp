#include "libstm/geometry/capsule_uv.h"

#include <cmath>

namespace sdm {

CapsuleUV capsule_uv(const CapsuleFrame& f, double w, double h, double d, const Eigen::Vector3d& p) {
  const Eigen::Vector3d ab = f.b - f.a;
  const double len = ab.norm();
  const Eigen::Vector3d axis = len > 0 ? Eigen::Vector3d(ab / len) : f.e1.cross(f.e2);
  const Eigen::Vector3d x = p - f.a;
  CapsuleUV r;
  r.t = len > 0 ? x.dot(axis) / len : 0.0;
  const double px = x.dot(f.e1), py = x.dot(f.e2);
  r.rho = std::hypot(px, py);
  r.phi = std::atan2(py, px);
  if (r.phi < 0) r.phi += 2 * M_PI;
  if (r.phi >= 2 * M_PI) r.phi = 0;  // -0 rounding
  r.u = h * r.phi / (2 * M_PI);
  const double quarter = M_PI / 2;
  if (r.t < 0) {
    const double theta = std::atan2(-x.dot(axis), r.rho);  // latitude below a's equator
    r.v = d * (1 - theta / quarter);
  } else if (r.t > 1) {
    const double theta = std::atan2((p - f.b).dot(axis), r.rho);
    r.v = w - d + d * theta / quarter;
  } else {
    r.v = d + r.t * (w - 2 * d);
  }
  return r;
}

}  // namespace sdm
