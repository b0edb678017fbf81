#include "libstm/geometry/capsule_ray.h"

#include <algorithm>
#include <cmath>

namespace sdm {

CapsuleRay capsule_ray(const CapsuleFrame& f, double w, double h, double d, double u, double v) {
  const Eigen::Vector3d ab = f.b - f.a;
  const Eigen::Vector3d axis = ab.normalized();
  const double phi = 2.0 * M_PI * u / h;
  const Eigen::Vector3d radial = std::cos(phi) * f.e1 + std::sin(phi) * f.e2;
  CapsuleRay r;
  if (v < d) {
    const double theta = (1.0 - std::max(v, 0.0) / d) * M_PI / 2;  // 0 at the equator, pi/2 at the pole
    r.origin = f.a;
    r.direction = std::cos(theta) * radial - std::sin(theta) * axis;
  } else if (v > w - d) {
    const double theta = std::min((v - (w - d)) / d, 1.0) * M_PI / 2;
    r.origin = f.b;
    r.direction = std::cos(theta) * radial + std::sin(theta) * axis;
  } else {
    const double t = w > 2 * d ? (v - d) / (w - 2 * d) : 0.5;
    r.origin = f.a + t * ab;
    r.direction = radial;
  }
  r.direction.normalize();
  return r;
}

}  // namespace sdm
