// Surface distance: checked against shapes whose distance is known in closed form.
#include "libstm/mesh/surface_distance.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/mesh/primitives.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

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

namespace {

// The nearest point of every face, by brute force: the reference for the tree's queries.
double brute_distance(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::Vector3d& p) {
  double best = INFINITY;
  for (int f = 0; f < F.rows(); ++f)
    best = std::min(best, (sdm::closest_point_on_triangle(p, V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2))) - p).norm());
  return best;
}

}  // namespace

TEST_CASE("Closest points started from a hint are the ones found without it", "[surface_distance]") {
  // The ypsilon bent (each vertex turned about the z axis by an angle growing with its height).
  const Mesh m = sdm::make_primitive("ypsilon");
  const Eigen::MatrixX3d V0 = vertex_matrix(m);
  const Eigen::MatrixX3i F = face_matrix(m);
  Eigen::MatrixX3d V1 = V0;
  const double zmin = V0.col(2).minCoeff(), zmax = V0.col(2).maxCoeff();
  for (int i = 0; i < V1.rows(); ++i) {
    const double a = 0.8 * (V0(i, 2) - zmin) / (zmax - zmin);
    V1(i, 0) = std::cos(a) * V0(i, 0) - std::sin(a) * V0(i, 1), V1(i, 1) = std::sin(a) * V0(i, 0) + std::cos(a) * V0(i, 1);
  }
  const TriangleBvh built(V1, F);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1.2, 1.2);
  const Eigen::Vector3d lo = V1.colwise().minCoeff(), hi = V1.colwise().maxCoeff();
  int hint = -1, hinted_far = 0;
  for (int q = 0; q < 400; ++q) {
    Eigen::Vector3d p;
    for (int k = 0; k < 3; ++k) p[k] = 0.5 * (lo[k] + hi[k]) + U(rng) * 0.5 * (hi[k] - lo[k]);
    const double truth = brute_distance(V1, F, p);
    INFO("query " << q);
    const auto plain = built.closest_point(p);
    CHECK(std::abs(plain.distance - truth) <= 1e-12);
    // The hint: the previous query's face (usually far), a face near the answer, none, or a bad index.
    const int given = q % 4 == 0 ? -1 : q % 4 == 1 ? hint : q % 4 == 2 ? built.closest_point(p + Eigen::Vector3d(0.01, 0, 0)).face : int(F.rows()) + 5;
    int h = given;
    const auto c = built.closest_point_near(p, h);
    CHECK(c.face == plain.face);  // the same face, ties included
    CHECK(c.point == plain.point);
    CHECK(h == c.face);
    hinted_far += q % 4 == 1 && given != c.face;
    // With a bound: nothing beyond it, the same point within it.
    int h2 = given;
    const auto bounded = built.closest_point_near(p, h2, 0.5 * truth);
    CHECK(bounded.face == -1);
    int h3 = given;
    CHECK(built.closest_point_near(p, h3, 2 * truth + 1e-9).face == plain.face);
    hint = c.face;
  }
  CHECK(hinted_far > 50);  // the previous query's face was mostly not the answer: the hints were exercised
  // Points just off a vertex, away from the centroid: the vertex is nearest, shared by all its
  // faces (exact ties), and each of its faces in turn is the hint.
  const Eigen::Vector3d centre = V1.colwise().mean();
  for (int f = 0; f < F.rows(); f += 7) {
    const Eigen::Vector3d v = V1.row(F(f, 0));
    const Eigen::Vector3d p = v + 1e-3 * (v - centre).normalized();
    const auto plain = built.closest_point(p);
    int h = f;
    const auto c = built.closest_point_near(p, h);
    INFO("face " << f);
    CHECK(c.face == plain.face);
    CHECK(c.point == plain.point);
  }
}

// Two sheets touching as limbs do, 0.01 apart and facing away from each other (the top of the lower
// one up, the bottom of the upper one down), each a fan of triangles: a point just above the lower
// sheet, with the lower sheet's normal, is nearest the upper sheet's back when it lies closer to
// it, and closest_point_facing keeps to the faces that face its way; brute force over the faces
// agrees, and with no face facing its way there is none.
TEST_CASE("Closest points facing a normal skip the sheet that faces away", "[surface_distance]") {
  Eigen::MatrixX3d V(8, 3);
  V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,           // lower sheet, z = 0, normal +z
      0, 0, 0.01, 1, 0, 0.01, 1, 1, 0.01, 0, 1, 0.01;  // upper sheet, z = 0.01, normal -z
  Eigen::MatrixX3i F(4, 3);
  F << 0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6;
  const sdm::TriangleBvh bvh(V, F);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), 0.004 + 0.005 * u(rng));  // nearer the upper sheet from 0.005 on
    const auto any = bvh.closest_point(p);
    const auto up = bvh.closest_point_facing(p, Eigen::Vector3d::UnitZ(), 0.0);
    REQUIRE(up.face >= 0);
    CHECK(up.face < 2);  // a face of the lower sheet
    CHECK(std::abs(up.distance - p.z()) < 1e-12);
    CHECK((up.point - Eigen::Vector3d(p.x(), p.y(), 0)).norm() < 1e-12);
    CHECK(any.distance <= up.distance + 1e-15);
    if (p.z() > 0.0051) CHECK(any.face >= 2);
    const auto down = bvh.closest_point_facing(p, -Eigen::Vector3d::UnitZ(), 0.0);
    CHECK(down.face >= 2);
    CHECK(std::abs(down.distance - (0.01 - p.z())) < 1e-12);
  }
  CHECK(bvh.closest_point_facing(Eigen::Vector3d(0.5, 0.5, 0.005), Eigen::Vector3d::UnitX(), 0.5).face == -1);
}
