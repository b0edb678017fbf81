// Atlas rendering (render_atlas): the remapped texture at every texel of a rectangle and its
// margins is the source texture at the surface point the capsule mapping sends there, and the
// push-pull fill leaves no empty (black) texel.
#include "libstm/render/gl_context.h"
#include "libstm/render/render_atlas.h"
#include "stm_test_scenes.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

TEST_CASE("push-pull fill reproduces smooth data in holes", "[render_atlas]") {
  // A linear ramp with a hole and a cleared border: the fill must stay within the ramp's range and
  // close to the ramp inside the hole (push-pull blends the surroundings).
  const int W = 64, H = 48;
  std::vector<float> v(W * H), w(W * H, 1.f);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) v[y * W + x] = float(x);
  for (int y = 20; y < 28; ++y)
    for (int x = 30; x < 36; ++x) w[y * W + x] = 0, v[y * W + x] = -1000;
  for (int x = 0; x < W; ++x) w[x] = 0, v[x] = -1000;
  sdm::push_pull_fill(v, w, W, H, 1);
  for (int y = 20; y < 28; ++y)
    for (int x = 30; x < 36; ++x) CHECK(std::abs(v[y * W + x] - x) < 3.0);
  for (int x = 0; x < W; ++x) CHECK(std::abs(v[x] - x) < 3.0);
  for (int y = 1; y < H; ++y)
    for (int x = 0; x < W; ++x)
      if (w[y * W + x] > 0) REQUIRE(v[y * W + x] == float(x));  // covered texels are kept
}

TEST_CASE("cylinder atlas holds the source texture at the capsule coordinates including margins", "[render_atlas]") {
  const int margin = 6;
  const stm_test::CylinderScene sc = stm_test::cylinder_scene(512, margin);
  const sdm::Image source = stm_test::procedural_image(512, 256);
  sdm::GlContext gl;
  std::vector<uint8_t> covered;
  const sdm::Image atlas = sdm::render_atlas(gl, sc.mesh, sc.layout, source, {}, &covered);
  REQUIRE(atlas.width == 512);
  const sdm::LayoutSegment& g = sc.layout.segments[0];
  const sdm::CapsuleFrame f = sdm::capsule_frame(sc.layout, 0);
  const Eigen::Vector3d axis = (f.b - f.a).normalized();
  // Texels of the cylinder part (v in [d, w - d], points of the side with y in [-0.5, 0.5]),
  // around the axis from -margin to h + margin: the periodic margins included.
  double se = 0, worst = 0;
  int n = 0, n_margin = 0;
  for (double u = -margin + 0.5; u < g.h + margin; u += 1)
    for (double v = std::ceil(g.d) + 0.5; v < g.w - g.d - 1; v += 1) {
      const Eigen::Vector2d a = sdm::local_to_atlas(g, u, v);
      const int x = int(a.x()), y = int(a.y());
      const double phi = 2 * M_PI * u / g.h, t = (v - g.d) / (g.w - 2 * g.d);
      const Eigen::Vector3d p = f.a + t * (f.b - f.a) + std::cos(phi) * f.e1 + std::sin(phi) * f.e2;
      REQUIRE(std::abs((p - f.a).dot(axis) - t) < 1e-9);
      const Eigen::Vector2d st = stm_test::cylinder_st(p, sc.uv_zero);
      const Eigen::Vector3d want = 255 * stm_test::procedural(st.x(), st.y());
      const uint8_t* got = atlas.at(x, atlas.height - 1 - y);
      for (int k = 0; k < 3; ++k) {
        const double e = got[k] - want[k];
        se += e * e;
        worst = std::max(worst, std::abs(e));
      }
      ++n;
      if (u < 0 || u > g.h) ++n_margin;
      // Every texel of the rectangle (and its periodic margin) was drawn from the surface.
      REQUIRE(covered[size_t(atlas.height - 1 - y) * atlas.width + x] == 255);
    }
  const double psnr = 10 * std::log10(255.0 * 255.0 / (se / (3.0 * n)));
  INFO("texels " << n << " (margin " << n_margin << "), PSNR " << psnr << " dB, worst " << worst);
  CHECK(n_margin >= 2 * margin * int(g.w - 2 * g.d - 2));
  CHECK(psnr > 35);
  CHECK(worst < 40);
  // No texel is left empty, and none is black: the procedural colours stay within [0.1, 0.9].
  for (size_t i = 0; i < atlas.pixels.size(); i += 4) {
    REQUIRE(atlas.pixels[i + 3] == 255);
    REQUIRE(std::max({atlas.pixels[i], atlas.pixels[i + 1], atlas.pixels[i + 2]}) >= 20);
  }
}

TEST_CASE("float attributes are interpolated into the atlas", "[render_atlas]") {
  // Corner value = the corner's height y: inside the cylinder part, texel value = the height of
  // the surface point mapped there.
  const stm_test::CylinderScene sc = stm_test::cylinder_scene(256, 4);
  std::vector<Eigen::Vector4f> values;
  for (auto f : sc.mesh.faces())
    for (auto v : sc.mesh.fv_range(f)) values.emplace_back(float(sc.mesh.point(v)[1]), 1.f, 0.f, 1.f);
  sdm::GlContext gl;
  const sdm::FloatImage img = sdm::render_atlas_values(gl, sc.mesh, sc.layout, values);
  const sdm::LayoutSegment& g = sc.layout.segments[0];
  double worst = 0;
  for (double u = 0.5; u < g.h; u += 3)
    for (double v = std::ceil(g.d) + 0.5; v < g.w - g.d - 1; v += 1) {
      const Eigen::Vector2d a = sdm::local_to_atlas(g, u, v);
      const double y = -0.5 + (v - g.d) / (g.w - 2 * g.d);
      worst = std::max(worst, std::abs(img.at(int(a.x()), img.height - 1 - int(a.y()))[0] - y));
    }
  CHECK(worst < 1e-3);
}
