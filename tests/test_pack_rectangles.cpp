#include "libstm/core/errors.h"
#include "libstm/layout/pack_rectangles.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

namespace {

struct Outer {
  int x0, y0, x1, y1;
};

// Checks the packing contract; returns the outer boxes.
// `grown`: rectangles may be larger than the packed size (max_anisotropy > 1).
std::vector<Outer> check_packing(const std::vector<Eigen::Vector2d>& sizes, const sdm::Packing& p, int S, int m, bool grown = false) {
  REQUIRE(p.rects.size() == sizes.size());
  std::vector<Outer> o;
  double inner = 0, outer = 0;
  for (size_t i = 0; i < sizes.size(); ++i) {
    const auto& r = p.rects[i];
    // floor(s * size) of the sizes rounded to 2^-30: within a texel of the unrounded product.
    CHECK(r.w - p.scale * sizes[i].x() >= -1);
    CHECK(r.h - p.scale * sizes[i].y() >= -1);
    if (!grown) {
      CHECK(r.w - p.scale * sizes[i].x() <= 1);
      CHECK(r.h - p.scale * sizes[i].y() <= 1);
    }
    CHECK(r.w >= 1);
    CHECK(r.h >= 1);
    const int ex = r.rotated ? r.h : r.w, ey = r.rotated ? r.w : r.h;
    o.push_back({r.x - m, r.y - m, r.x + ex + m, r.y + ey + m});
    CHECK(o.back().x0 >= 0);
    CHECK(o.back().y0 >= 0);
    CHECK(o.back().x1 <= S);
    CHECK(o.back().y1 <= S);
    inner += double(r.w) * r.h;
    outer += double(ex + 2 * m) * (ey + 2 * m);
  }
  for (size_t i = 0; i < o.size(); ++i)
    for (size_t j = i + 1; j < o.size(); ++j) {
      const bool apart = o[i].x1 <= o[j].x0 || o[j].x1 <= o[i].x0 || o[i].y1 <= o[j].y0 || o[j].y1 <= o[i].y0;
      CHECK(apart);
    }
  CHECK(p.coverage == Approx(outer / (double(S) * S)));
  CHECK(p.coverage_inner == Approx(inner / (double(S) * S)));
  return o;
}

// Rectangle sizes of capsules (w = L + 2d, h = 2 pi r, d = pi r / 2) like the paper's primitives.
Eigen::Vector2d capsule(double L, double r) { return {L + M_PI * r, 2 * M_PI * r}; }

}  // namespace

TEST_CASE("pack_rectangles: random sets never overlap and stay in the atlas", "[pack_rectangles]") {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> side(0.1, 5.0);
  std::uniform_int_distribution<int> count(1, 40);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = count(rng);
    std::vector<Eigen::Vector2d> sizes(n);
    for (auto& s : sizes) s = {side(rng), side(rng)};
    const int S = trial % 2 ? 1024 : 300, m = trial % 3;
    const auto p = sdm::pack_rectangles(sizes, S, m);
    check_packing(sizes, p, S, m);
    CHECK(p.coverage <= 1.0);
  }
}

// Many rectangles pack above 90 %; a handful of near-squares at one texel density cannot (seven
// equal squares fill 7/9 of a square at best), so those sets are held to the paper's Table II
// numbers (bottle 89.4 %, ypsilon 83.7 %) less a little.
TEST_CASE("pack_rectangles: sets like the paper's primitives pack as tightly as the paper's", "[pack_rectangles]") {
  struct Case {
    const char* name;
    std::vector<Eigen::Vector2d> sizes;
    double target = 0.90;
  };
  std::vector<Case> cases;
  {  // donut: 24 equal segments of a torus ring, R = 2, r = 0.5
    cases.push_back({"donut", std::vector<Eigen::Vector2d>(24, capsule(2 * 2 * std::sin(M_PI / 24), 0.5))});
  }
  {  // triple torus: three rings of 8 segments with different radii
    Case c{"triple-torus", {}};
    for (int k = 0; k < 8; ++k) c.sizes.push_back(capsule(0.8, 0.35)), c.sizes.push_back(capsule(0.7, 0.3)),
        c.sizes.push_back(capsule(0.9, 0.4));
    cases.push_back(c);
  }
  cases.push_back({"bottle", {capsule(1.5, 0.9), capsule(1.2, 0.85), capsule(0.8, 0.5), capsule(0.6, 0.3), capsule(1.0, 0.3)}, 0.87});
  cases.push_back({"ypsilon",
                   {capsule(1.0, 0.4), capsule(0.9, 0.4), capsule(0.8, 0.4), capsule(1.1, 0.35), capsule(1.0, 0.35),
                    capsule(0.9, 0.45), capsule(0.7, 0.45)}, 0.83});
  {
    Case c{"crossed-cylinders", {}};
    for (int k = 0; k < 6; ++k) c.sizes.push_back(capsule(0.6, 0.3)), c.sizes.push_back(capsule(0.5, 0.28));
    cases.push_back(c);
  }
  for (const auto& c : cases) {
    for (int margin : {0, 2}) {
      const auto p = sdm::pack_rectangles(c.sizes, 1024, margin);
      check_packing(c.sizes, p, 1024, margin);
      INFO(c.name << " margin " << margin << " coverage " << p.coverage << " inner " << p.coverage_inner);
      CHECK(p.coverage > c.target);
    }
  }
}

TEST_CASE("pack_rectangles: one rectangle fills its atlas side, rotation is used", "[pack_rectangles]") {
  // A single 3:1 rectangle: its long side must span the atlas (minus margins).
  const auto p = sdm::pack_rectangles({{3.0, 1.0}}, 512, 4);
  check_packing({{3.0, 1.0}}, p, 512, 4);
  CHECK(std::max(p.rects[0].w, p.rects[0].h) >= 512 - 8 - 1);
  // Two tall rectangles side by side: 2 x (1 x 2) fills the square.
  const std::vector<Eigen::Vector2d> two{{2.0, 1.0}, {2.0, 1.0}};
  const auto q = sdm::pack_rectangles(two, 256, 0);
  check_packing(two, q, 256, 0);
  CHECK(q.coverage > 0.99);
}

TEST_CASE("pack_rectangles: impossible requests are input errors", "[pack_rectangles]") {
  CHECK_THROWS_AS(sdm::pack_rectangles({}, 64, 0), sdm::InputError);
  CHECK_THROWS_AS(sdm::pack_rectangles({{1.0, -1.0}}, 64, 0), sdm::InputError);
  // 100 rectangles with 4-texel margins cannot fit in 16 x 16 texels.
  CHECK_THROWS_AS(sdm::pack_rectangles(std::vector<Eigen::Vector2d>(100, Eigen::Vector2d(1, 1)), 16, 4), sdm::InputError);
}

TEST_CASE("pack_rectangles: growing into leftover space keeps the packing valid and bounds the anisotropy", "[pack_rectangles]") {
  std::mt19937 rng(777);
  std::uniform_real_distribution<double> side(0.2, 4.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Eigen::Vector2d> sizes(3 + trial);
    for (auto& s : sizes) s = {side(rng), side(rng)};
    const int S = 512, m = trial % 3;
    const auto plain = sdm::pack_rectangles(sizes, S, m);
    const auto grown = sdm::pack_rectangles(sizes, S, m, 1.25);
    check_packing(sizes, grown, S, m, true);
    CHECK(grown.scale == plain.scale);
    CHECK(grown.coverage >= plain.coverage);
    CHECK(grown.coverage <= 1.0);
    for (size_t i = 0; i < sizes.size(); ++i) {
      // Growth never shrinks a side; the two sides' growth factors stay within 1.25 of each other.
      const auto& a = plain.rects[i];
      const auto& b = grown.rects[i];
      CHECK(b.w >= a.w);
      CHECK(b.h >= a.h);
      const double gw = double(b.w) / a.w, gh = double(b.h) / a.h;
      CHECK(std::max(gw, gh) / std::min(gw, gh) <= 1.25 + 1e-9);
    }
  }
}
