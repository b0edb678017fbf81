// Inside/outside and segment crossings (InsideMesh, over TriangleBvh's tree) checked against
// shapes whose volume is known in closed form: the cylinder and the capsule of radius 1 and the
// donut (torus of major radius 1, minor radius 0.4).
#include "libstm/mesh/inside_mesh.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/mesh/primitives.h"

#include <catch2/catch.hpp>
#include <cmath>

using namespace sdm;

namespace {

// A point at distance `r` from the z axis, at angle `a`, height `z`.
Eigen::Vector3d radial(double r, double a, double z) { return {r * std::cos(a), r * std::sin(a), z}; }

}  // namespace

TEST_CASE("Points at 0.9 of the radius are inside, at 1.1 outside", "[inside_mesh]") {
  for (const char* name : {"cylinder", "capsule"}) {
    INFO(name);
    const InsideMesh in(make_primitive(name));
    for (int k = 0; k < 24; ++k) {
      const double a = 0.37 + k * 2 * M_PI / 24, z = -0.9 + 1.8 * k / 23.0;
      CHECK(in.inside(radial(0.9, a, z)));
      CHECK_FALSE(in.inside(radial(1.1, a, z)));
    }
    CHECK(in.inside({0, 0, 0}));
    CHECK_FALSE(in.inside({0.1, 0.2, 2.5}));  // beyond the cap (cylinder z = 1, capsule z = 2)
    CHECK_FALSE(in.inside({5, -3, 0.5}));
  }
  const InsideMesh capsule(make_primitive("capsule"));
  CHECK(capsule.inside({0, 0, 1.9}));   // inside the hemisphere
  CHECK_FALSE(capsule.inside({0.8, 0, 1.8}));  // outside it: 0.8^2 + 0.8^2 > 1
}

TEST_CASE("Segments cross the wall, stay inside, or pass through the donut's hole", "[inside_mesh]") {
  const InsideMesh cyl(make_primitive("cylinder"));
  CHECK(cyl.segment_crosses({0, 0, 0}, {2, 0.1, 0.2}));      // inside to outside
  CHECK(cyl.segment_crosses({-2, 0.1, 0.3}, {2, -0.2, 0.1}));  // through, both ends outside
  CHECK_FALSE(cyl.segment_crosses({2, 2, 0}, {3, 2, 0.5}));   // outside, never near
  CHECK(cyl.segment_inside({-0.8, 0.1, -0.7}, {0.7, 0.2, 0.8}));
  CHECK_FALSE(cyl.segment_inside({0, 0, 0}, {0, 0, 1.5}));    // through the cap
  CHECK(cyl.triangle_crosses({0, 0, 0.1}, {0.5, 0.05, 0.1}, {2, 0.3, 0.15}));
  CHECK_FALSE(cyl.triangle_crosses({0, 0, 0}, {0.5, 0, 0.2}, {0, 0.5, -0.3}));

  const InsideMesh donut(make_primitive("donut"));
  CHECK(donut.inside({1, 0, 0}));
  CHECK(donut.inside({0, -1.2, 0.1}));
  CHECK_FALSE(donut.inside({0, 0, 0}));  // the hole
  CHECK_FALSE(donut.inside({1, 0, 0.5}));
  CHECK(donut.segment_crosses({1, 0, 0}, {-1, 0, 0}));  // across the hole
  CHECK(donut.segment_inside(radial(1, 0.1, 0), radial(1, 0.5, 0.1)));  // along the tube
  // A small loop around the tube's core spans no hole of the volume; a loop around the hole does.
  CHECK_FALSE(donut.triangle_crosses(radial(1, 0, 0.1), radial(1.1, 0.1, 0), radial(0.95, 0.05, -0.1)));
  CHECK(donut.triangle_crosses(radial(1, 0, 0), radial(1, 2.1, 0), radial(1, 4.2, 0)));
}

TEST_CASE("Rays cross a closed surface once from inside and twice from outside", "[inside_mesh]") {
  const Mesh cyl = make_primitive("cylinder");
  const TriangleBvh bvh(vertex_matrix(cyl), face_matrix(cyl));
  const Eigen::Vector3d d = Eigen::Vector3d(0.83, 0.31, 0.12).normalized();
  const Eigen::Vector3d p(0.1, -0.2, 0.3);
  CHECK(bvh.count_hits(p, d) == 1);
  CHECK(bvh.count_hits(p - 3 * d, d) == 2);
  CHECK(bvh.count_hits(p + 3 * d, d) == 0);  // past the surface, pointing away
  // The donut's two tubes along a line through the hole: four crossings from outside.
  const Mesh donut = make_primitive("donut");
  const TriangleBvh torus(vertex_matrix(donut), face_matrix(donut));
  CHECK(torus.count_hits({-3, 0.07, 0.05}, Eigen::Vector3d(1, 0.001, 0.002).normalized()) == 4);
  CHECK(torus.count_hits({0, 0.07, 0.05}, Eigen::Vector3d(1, 0.001, 0.002).normalized()) == 2);
  // any_hit looks within [t_min, t_max] only: the wall lies between the inscribed polygon's
  // apothem (> 0.99) and the radius 1.
  const Eigen::Vector3d o(0, 0, 0.137), x = radial(1, 0.05, 0);
  CHECK(bvh.any_hit(o, x, 0, 1.0));
  CHECK_FALSE(bvh.any_hit(o, x, 0, 0.95));
  CHECK(bvh.any_hit(o, x, 0, 2.0));
  CHECK_FALSE(bvh.any_hit(o, -x, 1.5, 3.0));  // the wall at t < 1 lies before the range
}
