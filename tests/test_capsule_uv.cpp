#include "libstm/geometry/capsule_uv.h"

#include <catch2/catch.hpp>
#include <cmath>

using Eigen::Vector3d;

namespace {

// A capsule of radius r along z from a = 0 to b = (0, 0, L), frame e1 = x, e2 = y, and a
// rectangle sized as the layout sizes it (w = L + 2d, h = 2 pi r, d = pi r / 2), in texels of
// `k` per unit.
struct Setup {
  double r = 0.7, L = 2.5, k = 40;
  sdm::CapsuleFrame f{{0, 0, 0}, {0, 0, 2.5}, {1, 0, 0}, {0, 1, 0}};
  double d = k * M_PI * r / 2, w = k * L + 2 * d, h = k * 2 * M_PI * r;
};

}  // namespace

TEST_CASE("capsule_uv: on the cylinder u is linear in the angle and v in the axial parameter", "[capsule_uv]") {
  Setup s;
  for (int i = 0; i < 16; ++i)
    for (int j = 0; j <= 10; ++j) {
      const double phi = 2 * M_PI * i / 16 + 0.01, z = s.L * j / 10;
      const Vector3d p(s.r * std::cos(phi), s.r * std::sin(phi), z);
      const auto c = sdm::capsule_uv(s.f, s.w, s.h, s.d, p);
      CHECK(c.phi == Approx(phi).margin(1e-12));
      CHECK(c.u == Approx(s.h * phi / (2 * M_PI)).margin(1e-9));
      CHECK(c.v == Approx(s.d + z / s.L * (s.w - 2 * s.d)).margin(1e-9));
      // Isotropic: the rectangle has k texels per unit along and around the cylinder.
      CHECK((c.v - s.d) == Approx(s.k * z).margin(1e-9));
      CHECK(c.u == Approx(s.k * s.r * phi).margin(1e-9));
    }
}

TEST_CASE("capsule_uv: caps meet the cylinder at the equator and end at the poles", "[capsule_uv]") {
  Setup s;
  for (double phi : {0.3, 2.0, 4.5}) {
    const Vector3d dir(std::cos(phi), std::sin(phi), 0);
    for (double eps : {1e-6, 1e-9}) {
      const auto below_a = sdm::capsule_uv(s.f, s.w, s.h, s.d, s.r * dir + Vector3d(0, 0, -eps));
      const auto above_a = sdm::capsule_uv(s.f, s.w, s.h, s.d, s.r * dir + Vector3d(0, 0, eps));
      CHECK(below_a.v == Approx(above_a.v).margin(1e-4));
      CHECK(below_a.u == Approx(above_a.u).margin(1e-9));
      const auto below_b = sdm::capsule_uv(s.f, s.w, s.h, s.d, s.r * dir + Vector3d(0, 0, s.L - eps));
      const auto above_b = sdm::capsule_uv(s.f, s.w, s.h, s.d, s.r * dir + Vector3d(0, 0, s.L + eps));
      CHECK(below_b.v == Approx(above_b.v).margin(1e-4));
    }
    // Latitude theta on the caps: v = d (1 - theta / (pi/2)) at a, w - d + d theta / (pi/2) at b.
    for (double theta : {0.2, M_PI / 4, 1.3}) {
      const Vector3d pa = s.r * (std::cos(theta) * dir - std::sin(theta) * Vector3d::UnitZ());
      const Vector3d pb = Vector3d(0, 0, s.L) + s.r * (std::cos(theta) * dir + std::sin(theta) * Vector3d::UnitZ());
      const auto ca = sdm::capsule_uv(s.f, s.w, s.h, s.d, pa), cb = sdm::capsule_uv(s.f, s.w, s.h, s.d, pb);
      CHECK(ca.v == Approx(s.d * (1 - theta / (M_PI / 2))).margin(1e-9));
      CHECK(cb.v == Approx(s.w - s.d + s.d * theta / (M_PI / 2)).margin(1e-9));
      CHECK(ca.u == Approx(s.h * phi / (2 * M_PI)).margin(1e-9));
      // On a hemisphere of radius r the meridian has length r theta: d = pi r / 2 keeps it isotropic.
      CHECK((s.d - ca.v) == Approx(s.k * s.r * theta).margin(1e-9));
    }
  }
  CHECK(sdm::capsule_uv(s.f, s.w, s.h, s.d, {0, 0, -s.r}).v == Approx(0).margin(1e-12));
  CHECK(sdm::capsule_uv(s.f, s.w, s.h, s.d, {0, 0, s.L + s.r}).v == Approx(s.w).margin(1e-9));
}

TEST_CASE("capsule_uv: coordinates stay in the rectangle and move with the frame", "[capsule_uv]") {
  Setup s;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Vector3d t(3, -1, 2);
  const sdm::CapsuleFrame g{R * s.f.a + t, R * s.f.b + t, R * s.f.e1, R * s.f.e2};
  for (int i = 0; i < 200; ++i) {
    // Points all around the capsule, at several distances from the axis.
    const double phi = 0.1 + 0.031 * i, z = -1.2 + 0.025 * i, rho = 0.3 + 0.004 * i;
    const Vector3d p(rho * std::cos(phi), rho * std::sin(phi), z);
    const auto c = sdm::capsule_uv(s.f, s.w, s.h, s.d, p);
    const auto c2 = sdm::capsule_uv(g, s.w, s.h, s.d, R * p + t);
    CHECK(c.u >= 0);
    CHECK(c.u < s.h);
    CHECK(c.v >= 0);
    CHECK(c.v <= s.w);
    CHECK(c2.u == Approx(c.u).margin(1e-8));
    CHECK(c2.v == Approx(c.v).margin(1e-8));
  }
}
