// spatially_ordered renumbers a mesh so that neighbours sit near each other in memory, without
// changing the surface: the same corner points, orientation and uv per face.
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/primitives.h"
#include "libstm/mesh/spatial_order.h"

#include <catch2/catch.hpp>
#include <algorithm>
#include <map>
#include <numeric>
#include <random>

using namespace sdm;

namespace {

// The median, over faces, of the largest difference between two corners' vertex numbers.
double median_corner_spread(const Mesh& m) {
  std::vector<int> spread;
  for (auto f : m.faces()) {
    int lo = 1 << 30, hi = -1;
    for (auto v : m.fv_range(f)) lo = std::min(lo, v.idx()), hi = std::max(hi, v.idx());
    spread.push_back(hi - lo);
  }
  std::nth_element(spread.begin(), spread.begin() + long(spread.size() / 2), spread.end());
  return spread[spread.size() / 2];
}

// Each face as its three corner points, in its own corner order from the smallest point, with uv.
std::multimap<std::array<double, 9>, std::array<double, 6>> faces_by_points(const Mesh& m) {
  std::multimap<std::array<double, 9>, std::array<double, 6>> out;
  for (auto f : m.faces()) {
    std::vector<std::pair<Mesh::Point, Mesh::TexCoord2D>> c;
    for (auto h : m.fh_range(f)) c.emplace_back(m.point(h.to()), m.texcoord2D(h));
    std::rotate(c.begin(), std::min_element(c.begin(), c.end(), [](auto& a, auto& b) { return a.first < b.first; }), c.end());
    std::array<double, 9> key{};
    std::array<double, 6> uv{};
    for (size_t i = 0; i < 3; ++i)
      for (size_t k = 0; k < 3; ++k) key[3 * i + k] = c[i].first[int(k)];
    for (size_t i = 0; i < 3; ++i) uv[2 * i] = c[i].second[0], uv[2 * i + 1] = c[i].second[1];
    out.emplace(key, uv);
  }
  return out;
}

}  // namespace

TEST_CASE("spatially_ordered keeps the surface and brings neighbours together", "[spatial_order]") {
  // The bottle with its vertices and faces numbered at random, uv from the positions.
  const Mesh bottle = make_primitive("bottle", 8000);
  std::vector<int> perm(bottle.n_vertices());
  std::iota(perm.begin(), perm.end(), 0);
  std::mt19937 rng(3);
  std::shuffle(perm.begin(), perm.end(), rng);
  MeshSoup soup;
  soup.points.resize(perm.size());
  for (auto v : bottle.vertices()) soup.points[size_t(perm[size_t(v.idx())])] = point(bottle, v);
  for (auto f : bottle.faces()) {
    std::array<int, 3> t{};
    int c = 0;
    for (auto v : bottle.fv_range(f)) t[size_t(c++)] = perm[size_t(v.idx())];
    soup.triangles.push_back(t);
  }
  std::shuffle(soup.triangles.begin(), soup.triangles.end(), rng);
  for (const auto& t : soup.triangles)
    for (int v : t) soup.uv.emplace_back(soup.points[size_t(v)].x() * 0.3, soup.points[size_t(v)].z() * 0.2 + 0.1);
  const Mesh scattered = build_mesh(soup);
  const Mesh ordered = spatially_ordered(scattered);

  REQUIRE(ordered.n_vertices() == scattered.n_vertices());
  REQUIRE(ordered.n_faces() == scattered.n_faces());
  CHECK(faces_by_points(ordered) == faces_by_points(scattered));  // same corners, orientation and uv
  const double before = median_corner_spread(scattered), after = median_corner_spread(ordered);
  INFO("median corner spread " << before << " -> " << after << " of " << ordered.n_vertices() << " vertices");
  CHECK(before > 0.2 * double(ordered.n_vertices()));
  CHECK(after < 0.02 * double(ordered.n_vertices()));
  CHECK(scattered_numbering(scattered));
  CHECK_FALSE(scattered_numbering(ordered));
  CHECK_FALSE(scattered_numbering(bottle));  // as make_primitive numbers it
  // Faces follow their vertices: consecutive faces share or neighbour their smallest corner.
  long jumps = 0, previous = -1;
  for (auto f : ordered.faces()) {
    int lo = 1 << 30;
    for (auto v : ordered.fv_range(f)) lo = std::min(lo, v.idx());
    jumps += lo < previous;
    previous = lo;
  }
  CHECK(jumps == 0);
}
