// Atlas pictures: the checkerboard follows each rectangle's local (u, v) and wraps around the axis.
#include "libstm/layout/draw_atlas.h"
#include "libstm/core/image.h"
#include "libstm/layout/layout.h"
#include "libstm/layout/compute_layout.h"
#include "tests/synthetic_shapes.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>

using namespace sdm;

TEST_CASE("The checker atlas alternates every square texels along u and v in each rectangle", "[draw_atlas]") {
  const synth::Shape shape = synth::capsule(0.5, 3.0, 4);
  LayoutOptions lo;
  lo.size = 256;
  const Layout layout = compute_layout(shape.mesh, shape.skeleton, lo);
  const int square = 8;
  const Image im = checker_atlas(layout, square);
  REQUIRE(im.width == 256);
  auto lum = [&](int x, int y) {
    const uint8_t* p = &im.pixels[(size_t(im.height - 1 - y) * im.width + x) * 4];
    return int(p[0]) + p[1] + p[2];
  };
  long checked = 0;
  for (const auto& seg : layout.segments) {
    const int ex = seg.rotated ? seg.h : seg.w, ey = seg.rotated ? seg.w : seg.h;
    for (int y = seg.y; y + square < seg.y + ey; y += 3)
      for (int x = seg.x; x + square < seg.x + ex; x += 3) {
        // One square further along either atlas axis flips the shade.
        CHECK(lum(x, y) != lum(x + square, y));
        CHECK(lum(x, y) != lum(x, y + square));
        ++checked;
      }
  }
  CHECK(checked > 100);
}

TEST_CASE("sdm render --checker draws the STM checkerboard and needs a layout", "[draw_atlas]") {
  test_util::TempDir dir;
  const synth::Shape shape = synth::capsule(0.5, 3.0, 4);
  write_mesh(shape.mesh, dir / "capsule.off");
  write_skeleton_json(shape.skeleton, dir / "capsule.skel.json");
  REQUIRE(test_util::run_sdm("stm " + (dir / "capsule.off") + " --skeleton " + (dir / "capsule.skel.json") + " -o " +
                             (dir / "capsule.layout.json") + " --size 256")
              .exit_code == 0);
  auto r = test_util::run_sdm("render " + (dir / "capsule.off") + " --layout " + (dir / "capsule.layout.json") +
                              " --checker --unlit -o " + (dir / "view.png") + " --width 128 --height 128");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const Image view = read_png(dir / "view.png");
  // Both shades of the checkerboard are visible on the object.
  int light = 0, dark = 0;
  for (size_t i = 0; i < size_t(view.width) * view.height; ++i) {
    const uint8_t* p = &view.pixels[4 * i];
    const int sum = p[0] + p[1] + p[2];
    if (sum == 765) continue;  // background
    (sum > 400 ? light : dark)++;
  }
  CHECK(light > 200);
  CHECK(dark > 200);
  CHECK(test_util::run_sdm("render " + (dir / "capsule.off") + " --checker -o " + (dir / "x.png")).exit_code == 2);
}
