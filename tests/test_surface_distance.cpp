// Surface distance: checked against shapes whose distance is known in closed form.
#include "libstm/mesh/surface_distance.h"
#include "libstm/geometry/triangle_bvh.h"

#include <catch2/catch.hpp>
#include <cmath>

using namespace sdm;

namespace {

// Axis-aligned box [-s, s]^3 as 12 triangles, outward oriented.
Mesh box(double s) {
  Mesh m;
  Mesh::VertexHandle v[8];
  for (int i = 0; i < 8; ++i) v[i] = m.add_vertex({(i & 1) ? s : -s, (i & 2) ? s : -s, (i & 4) ? s : -s});
  const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (auto& f : q) {
    m.add_face(v[f[0]], v[f[1]], v[f[2]]);
    m.add_face(v[f[0]], v[f[2]], v[f[3]]);
  }
  return m;
}

}  // namespace

TEST_CASE("Closest points on a triangle cover its regions", "[surface_distance]") {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  CHECK((closest_point_on_triangle({0.2, 0.2, 1}, a, b, c) - Eigen::Vector3d(0.2, 0.2, 0)).norm() < 1e-15);
  CHECK((closest_point_on_triangle({-1, -1, 0}, a, b, c) - a).norm() < 1e-15);
  CHECK((closest_point_on_triangle({0.5, -2, 0}, a, b, c) - Eigen::Vector3d(0.5, 0, 0)).norm() < 1e-15);
  CHECK((closest_point_on_triangle({1, 1, 0}, a, b, c) - Eigen::Vector3d(0.5, 0.5, 0)).norm() < 1e-15);
}

TEST_CASE("Nested boxes are at the distance of their half-size difference", "[surface_distance]") {
  // Every point of the inner box [-1,1]^3 is 0.5 from the outer [-1.5,1.5]^3 at least; face
  // centres exactly 0.5, corners 0.5*sqrt(3) away from the outer corners: Hausdorff is the
  // largest distance of an outer point to the inner box, i.e. the corner gap 0.5*sqrt(3).
  const Mesh inner = box(1.0), outer = box(1.5);
  const SurfaceDistance d = surface_distance(inner, outer, 20000);
  CHECK(d.hausdorff == Approx(0.5 * std::sqrt(3.0)).epsilon(0.02));
  CHECK(d.hausdorff <= 0.5 * std::sqrt(3.0) + 1e-12);
  CHECK(d.mean > 0.5 - 1e-12);  // no sample is closer than the face gap
  CHECK(d.rms < 0.5 * std::sqrt(3.0));
  CHECK(d.diagonal == Approx(2 * std::sqrt(3.0)));
}

TEST_CASE("A surface is at zero distance from itself and rays hit where expected", "[surface_distance]") {
  const Mesh m = box(1.0);
  const SurfaceDistance d = surface_distance(m, m, 5000);
  CHECK(d.hausdorff < 1e-12);
  const TriangleBvh bvh(vertex_matrix(m), face_matrix(m));
  auto hit = bvh.first_hit({0.1, 0.2, 0}, Eigen::Vector3d(1, 0, 0));
  CHECK(hit.face >= 0);
  CHECK(hit.t == Approx(0.9));
  CHECK(bvh.count_hits({0.1, 0.2, 0.3}, Eigen::Vector3d(0.3, 0.5, 0.8).normalized()) == 1);  // inside: odd
  CHECK(bvh.count_hits({3, 0.2, 0.3}, Eigen::Vector3d(-1, 0.01, 0.02).normalized()) == 2);   // outside: even
}
