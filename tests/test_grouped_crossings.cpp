// The crossing search of the decoder's untangling (grouped_crossings.h) finds exactly the pairs that
// the search over the whole mesh (crossing_face_pairs, CGAL's count) finds between near groups, at
// first and again after some points move.
#include "libsdm/decode/tessellate_mesh.h"
#include "libstm/mesh/grouped_crossings.h"
#include "libstm/mesh/self_intersections.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <random>

using namespace sdm;

namespace {

struct Sphere {
  Eigen::MatrixX3i base, triangles;
  std::vector<int> triangle_face;
  std::vector<Eigen::Vector3d> points;
  std::vector<std::vector<int>> near;  // base faces sharing a corner
};

// An icosahedron's faces cut into rate^2 triangles each, the points on the unit sphere.
Sphere sphere(int rate) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  Eigen::MatrixX3d V(12, 3);
  V << -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1, -t, 0, -1, -t, 0, 1;
  Sphere s;
  s.base.resize(20, 3);
  s.base << 0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2,
      6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1;
  const Tessellation tess = tessellate_mesh(s.base, std::vector<int>(20, rate));
  s.triangles = tess.triangles;
  s.triangle_face = tess.triangle_face;
  for (size_t i = 0; i < tess.point_face.size(); ++i) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c) p += tess.point_bary[i][c] * V.row(s.base(tess.point_face[i], c)).transpose();
    s.points.push_back(p.normalized());
  }
  s.near.resize(20);
  for (int f = 0; f < 20; ++f)
    for (int g = 0; g < 20; ++g)
      if ((s.base.row(f).replicate(3, 1).array() == s.base.row(g).transpose().replicate(1, 3).array()).any()) s.near[f].push_back(g);
  return s;
}

Eigen::MatrixX3d matrix(const std::vector<Eigen::Vector3d>& p) {
  Eigen::MatrixX3d V(Eigen::Index(p.size()), 3);
  for (size_t i = 0; i < p.size(); ++i) V.row(Eigen::Index(i)) = p[i];
  return V;
}

// The pairs of the whole mesh's search whose faces' base faces share a corner, and which have a
// flagged face (any when `faces` is empty).
std::vector<std::array<int, 2>> near_pairs(const Sphere& s, const std::vector<char>& faces, long& far) {
  std::vector<std::array<int, 2>> out;
  far = 0;
  for (const auto& p : crossing_face_pairs(matrix(s.points), s.triangles, faces)) {
    const auto& n = s.near[size_t(s.triangle_face[size_t(p[0])])];
    if (std::find(n.begin(), n.end(), s.triangle_face[size_t(p[1])]) != n.end())
      out.push_back(p);
    else
      ++far;
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST_CASE("Grouped crossing search finds the whole mesh's crossing pairs between near groups", "[grouped_crossings]") {
  Sphere s = sphere(8);  // 1280 triangles, edges about 0.13
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.12, 0.12);
  for (auto& p : s.points) p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  // A spike through the sphere: a point pushed to beyond the opposite side crosses far faces.
  s.points[100] *= -1.3;
  GroupedCrossings search(s.triangles, s.triangle_face, s.near, s.points);
  long far = 0;
  const auto expected = near_pairs(s, {}, far);
  const auto found = search.find(s.points);
  std::printf("grouped crossings: %zu near pairs found, %zu expected, %ld far pairs left out\n", found.size(), expected.size(), far);
  CHECK(expected.size() > 100);  // the noise (up to an edge) folds many neighbouring faces
  CHECK(far > 0);                // the spike's
  CHECK(found == expected);

  // Points of a few base faces move (flattened back onto the sphere): the faces they touch are
  // flagged, and the search with the flags gives the pairs with a flagged face.
  std::vector<char> moved(s.points.size(), 0), faces(size_t(s.triangles.rows()), 0);
  for (Eigen::Index t = 0; t < s.triangles.rows(); ++t)
    if (s.triangle_face[size_t(t)] % 5 == 0)
      for (int c = 0; c < 3; ++c) moved[size_t(s.triangles(t, c))] = 1;
  for (size_t i = 0; i < s.points.size(); ++i)
    if (moved[i] && i != 100) s.points[i].normalize();
  for (Eigen::Index t = 0; t < s.triangles.rows(); ++t)
    for (int c = 0; c < 3; ++c) faces[size_t(t)] |= moved[size_t(s.triangles(t, c))];
  const auto expected_moved = near_pairs(s, faces, far);
  const auto found_moved = search.find(s.points, faces);
  CHECK(expected_moved.size() > 10);
  CHECK(expected_moved.size() < expected.size());
  CHECK(found_moved == expected_moved);
  // And every pair again, unflagged: the trees were refitted where the points moved.
  CHECK(search.find(s.points) == near_pairs(s, {}, far));
}
