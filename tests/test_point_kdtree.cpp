// The point k-d tree (point_kdtree.h) against a brute-force search: the same neighbours in the same
// order, ties to the smaller index, on scattered points and on a grid full of equal distances.
#include "libstm/geometry/point_kdtree.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>
#include <random>

namespace {

// The k nearest by sorting every point by (squared distance, index).
std::vector<int> brute_nearest(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& q, int k, std::vector<double>& sq) {
  std::vector<int> order(pts.size());
  std::iota(order.begin(), order.end(), 0);
  auto key = [&](int i) { return std::pair((pts[size_t(i)] - q).squaredNorm(), i); };
  std::sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
  order.resize(std::min(order.size(), size_t(k)));
  sq.clear();
  for (int i : order) sq.push_back(key(i).first);
  return order;
}

void check_against_brute(const std::vector<Eigen::Vector3d>& pts, const std::vector<Eigen::Vector3d>& queries) {
  const sdm::PointKdTree tree(pts);
  REQUIRE(tree.size() == int(pts.size()));
  for (const Eigen::Vector3d& q : queries)
    for (int k : {1, 2, 7, 20, 64}) {
      std::vector<double> sq, brute_sq;
      const std::vector<int> got = tree.nearest(q, k, &sq);
      CHECK(got == brute_nearest(pts, q, k, brute_sq));
      CHECK(sq == brute_sq);
      double d1 = -1;
      CHECK(tree.nearest_one(q, &d1) == got[0]);
      CHECK(d1 == sq[0]);
    }
  for (const Eigen::Vector3d& q : queries) {
    const double r = 0.15;
    std::vector<int> within = tree.within(q, r), brute;
    std::sort(within.begin(), within.end());
    for (int i = 0; i < int(pts.size()); ++i)
      if ((pts[size_t(i)] - q).squaredNorm() <= r * r) brute.push_back(i);
    CHECK(within == brute);
  }
}

}  // namespace

TEST_CASE("point k-d tree: nearest and within agree with a brute-force search, ties to the smaller index", "[point_cloud][kdtree]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Vector3d> scattered(3000), queries(200);
  for (auto& p : scattered) p = {u(rng), u(rng), 0.2 * u(rng)};
  for (auto& q : queries) q = {1.2 * u(rng), 1.2 * u(rng), u(rng)};
  check_against_brute(scattered, queries);
  // A 12^3 grid queried at grid points and cell centres: many neighbours at equal distances, and
  // every coordinate equal to some split.
  std::vector<Eigen::Vector3d> grid;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j)
      for (int k = 0; k < 12; ++k) grid.push_back(0.1 * Eigen::Vector3d(i, j, k));
  std::vector<Eigen::Vector3d> at_grid;
  for (int i = 0; i < 60; ++i) at_grid.push_back(grid[size_t(i * 29 % grid.size())] + (i % 2 ? Eigen::Vector3d(0.05, 0.05, 0.05) : Eigen::Vector3d::Zero()));
  check_against_brute(grid, at_grid);
  // Fewer points than asked for: every point, nearest first; no points: nothing.
  const std::vector<Eigen::Vector3d> three = {{0, 0, 0}, {1, 0, 0}, {3, 0, 0}};
  const sdm::PointKdTree small(three);
  CHECK(small.nearest({2.9, 0, 0}, 10) == std::vector<int>{2, 1, 0});
  const std::vector<Eigen::Vector3d> none;
  const sdm::PointKdTree empty(none);
  CHECK(empty.nearest({0, 0, 0}, 3).empty());
  CHECK(empty.nearest_one({0, 0, 0}) == -1);
  CHECK(empty.within({0, 0, 0}, 1.0).empty());
}

TEST_CASE("point k-d tree: a cloud's spacing is its grid's step, over all points or every stride-th", "[point_cloud][kdtree]") {
  std::vector<Eigen::Vector3d> grid;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 10; ++k) grid.push_back(0.25 * Eigen::Vector3d(i, j, k));
  const sdm::PointKdTree tree(grid);
  CHECK(std::abs(sdm::mean_nearest_distance(grid, tree) - 0.25) < 1e-12);
  CHECK(std::abs(sdm::mean_nearest_distance(grid, tree, 7) - 0.25) < 1e-12);
  const std::vector<Eigen::Vector3d> one{Eigen::Vector3d(1, 2, 3)};
  CHECK(sdm::mean_nearest_distance(one, sdm::PointKdTree(one)) == 0.0);
}
