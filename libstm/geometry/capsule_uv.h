#pragma once
/// The capsule mapping (paper 3.3, DESIGN 4.5): one pure function, mirrored line by line in the
/// GLSL shaders (keep them in step; the tests compare both).
///
/// Segment a -> b, axis = (b - a)/|b - a|, frame e1, e2 (e2 = axis x e1), rectangle of width w along
/// the axis (caps included) and height h around it, cap length d (all in the same unit, e.g. texels).
/// For a point p:
///   t   = (p - a).axis / |b - a|
///   phi = atan2((p - a).e2, (p - a).e1) in [0, 2 pi)        (angle around the axis, from e1)
///   u   = h phi / (2 pi)                                    (around the axis, 0 <= u < h)
///   v   = d + t (w - 2d)                      if 0 <= t <= 1 (cylinder)
///   v   = d (1 - theta / (pi/2))              if t < 0, theta = latitude of p - a from the equator
///   v   = w - d + d theta / (pi/2)            if t > 1, theta = latitude of p - b from the equator
/// Both caps meet the cylinder at their equator (theta = 0, v = d and v = w - d), and their poles
/// land on the rectangle's ends (v = 0 and v = w).
#include <Eigen/Dense>

namespace sdm {

struct CapsuleFrame {
  Eigen::Vector3d a, b;  ///< segment end nodes
  Eigen::Vector3d e1;    ///< reference direction (phi = 0), orthogonal to the axis
  Eigen::Vector3d e2;    ///< axis x e1 (phi = pi/2)
};

struct CapsuleUV {
  double u = 0, v = 0;  ///< local rectangle coordinates: u in [0, h) around, v in [0, w] along the axis
  double phi = 0;       ///< angle around the axis in [0, 2 pi)
  double t = 0;         ///< axial parameter (unclamped)
  double rho = 0;       ///< distance from the axis (0 at a pole: phi is then meaningless)
};

CapsuleUV capsule_uv(const CapsuleFrame& f, double w, double h, double d, const Eigen::Vector3d& p);

}  // namespace sdm
