#pragma once
/// The test shapes of the paper (Table I) and two analytic shapes, as deterministic closed,
/// 2-manifold, outward-oriented triangle meshes with well-shaped triangles (smallest angle above
/// kPrimitiveMinAngleDegrees). Same name and resolution, same mesh, byte for byte.
#include "libstm/mesh/mesh.h"

#include <string>
#include <vector>

namespace sdm {

/// Shapes (default vertex count in brackets, genus):
///   ypsilon            [480, genus 0]  three round tubes (radius 0.22) meeting smoothly in a Y,
///                                      ends capped round; in the plane z = 0.
///   bottle             [1530, genus 1] a jug: rounded body (radius 0.6, z in [0, 1.6]), a neck up to
///                                      z = 2.52 and a handle (a tube joining the body at two places).
///   donut              [1728, genus 1] torus around z: major radius 1, minor radius 0.4.
///   triple-torus       [2256, genus 3] three tori (radii 1 and 0.3) fused smoothly in a row along x.
///   crossed-cylinders  [3660, genus 0] two perpendicular capped cylinders (radius 0.5, length 4,
///                                      along x and y, edges rounded) crossing at the origin.
///   cylinder           [1200, genus 0] axis z, radius 1, z in [-1, 1], flat caps. Every vertex lies
///                                      on the side (x^2 + y^2 = 1) or on a cap (|z| = 1, x^2 + y^2 <= 1).
///   capsule            [1200, genus 0] axis z, radius 1: the cylinder x^2 + y^2 = 1, z in [-1, 1],
///                                      closed by hemispheres of radius 1 centred at (0, 0, +-1)
///                                      (total length 4). Every vertex lies on that surface.
///   two-tunnels        [4000, genus 2] a thick bar along x (radius 0.8, length 3.2, ends rounded)
///                                      with two small tunnels along y (radius 0.15, at x = +-0.7):
///                                      the skeleton must keep one cycle per tunnel.
///   mushroom           [3000, genus 0] a thin cap (spherical shell of radius 1, 0.16 thick, above
///                                      z = 0.35) over a stem (radius 0.2, down to z = -1.3).
/// The blended shapes are smooth implicit surfaces (smooth unions of distance fields), polygonised
/// and isotropically remeshed, their vertices projected onto the implicit surface; the donut,
/// cylinder and capsule are surfaces of revolution sampled exactly.
/// `resolution` is the approximate number of vertices wanted (the shape stays the same, only the
/// sampling density changes; the count usually lands within 5 %, within 15 % at the smallest
/// counts); 0 means the default above. Time grows about linearly with the resolution.
/// \throw InputError for an unknown name (the message lists the valid ones) or a resolution
/// outside [200, 1000000].
Mesh make_primitive(const std::string& name, int resolution = 0);

/// The valid names, in the order of the paper's Table I followed by the analytic shapes and the
/// tunnelled bar.
std::vector<std::string> primitive_names();

/// A lower bound on the smallest triangle angle of every primitive, in degrees, at every resolution
/// from 200 to 50000 vertices (tests/test_primitives.cpp).
constexpr double kPrimitiveMinAngleDegrees = 20.0;

}  // namespace sdm
