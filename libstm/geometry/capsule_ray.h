#pragma once
/// The inverse of the capsule mapping (capsule_uv.h): local rectangle coordinates (u, v) -> the ray
/// from the capsule's core through the surface points that map there. For the cylinder part the
/// ray starts on the axis at parameter t and points away from it at angle phi; on a cap it starts at
/// the cap's centre node and points at latitude theta. capsule_uv(origin + s * direction) gives
/// back (u, v) for every s > 0: this is what the displacement map samples and rebuilds.
#include "libstm/geometry/capsule_uv.h"

namespace sdm {

struct CapsuleRay {
  Eigen::Vector3d origin, direction;  ///< direction has unit length
};

CapsuleRay capsule_ray(const CapsuleFrame& f, double w, double h, double d, double u, double v);

}  // namespace sdm
