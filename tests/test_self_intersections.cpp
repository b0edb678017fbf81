// find_self_intersections: pairs of faces that cross, counted the same way on one thread or two.
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "libstm/mesh/self_intersections.h"

#include <catch2/catch.hpp>

using namespace sdm;

namespace {

// A capsule (radius 1, axis z) with a small capsule (radius 0.3) pushed through its side at
// (1, 0, 0.5); the small one's faces in the middle of the large one's, so that the crossing pairs
// come from both halves of the face list.
void crossed_capsules(Eigen::MatrixX3d& V, Eigen::MatrixX3i& F, int large_vertices) {
  const Mesh big = make_primitive("capsule", large_vertices), small = make_primitive("capsule", 1000);
  const Eigen::MatrixX3d Vb = vertex_matrix(big), Vs = vertex_matrix(small);
  const Eigen::MatrixX3i Fb = face_matrix(big), Fs = face_matrix(small);
  V.resize(Vb.rows() + Vs.rows(), 3);
  V.topRows(Vb.rows()) = Vb;
  for (int i = 0; i < Vs.rows(); ++i) V.row(Vb.rows() + i) = 0.3 * Vs.row(i) + Eigen::RowVector3d(1, 0, 0.5);
  const int half = int(Fb.rows() / 2);
  F.resize(Fb.rows() + Fs.rows(), 3);
  F.topRows(half) = Fb.topRows(half);
  F.middleRows(half, Fs.rows()) = Fs.array() + int(Vb.rows());
  F.bottomRows(Fb.rows() - half) = Fb.bottomRows(Fb.rows() - half);
}

}  // namespace

TEST_CASE("Self-intersections of a large mesh (two threads) are those of its crossing region alone (one thread)", "[self_intersections]") {
  Eigen::MatrixX3d V;
  Eigen::MatrixX3i F;
  crossed_capsules(V, F, 26000);
  REQUIRE(F.rows() >= 50000);  // the two-thread path
  // Only faces near the small capsule can cross: the same faces, in the same order, are few enough
  // for the one-thread path, and must give the same count and the same first crossing.
  std::vector<int> near;
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d c = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))).transpose() / 3;
    if ((c - Eigen::Vector3d(1, 0, 0.5)).norm() < 1.0) near.push_back(f);
  }
  REQUIRE(near.size() < 50000);
  Eigen::MatrixX3i Fn(near.size(), 3);
  for (size_t k = 0; k < near.size(); ++k) Fn.row(k) = F.row(near[k]);
  const SelfIntersections all = find_self_intersections(V, F), region = find_self_intersections(V, Fn);
  INFO(all.pairs << " pairs against " << region.pairs << " in the region");
  CHECK(all.pairs > 100);  // a closed curve of crossings around the small capsule
  CHECK(all.pairs == region.pairs);
  CHECK(all.face_a == near[region.face_a]);
  CHECK(all.face_b == near[region.face_b]);
  CHECK((all.example - region.example).norm() == 0);
  // Stopping at max_pairs gives exactly max_pairs, and the same first crossing.
  const SelfIntersections some = find_self_intersections(V, F, all.pairs / 2);
  CHECK(some.pairs == all.pairs / 2);
  CHECK(some.face_a == all.face_a);
  // The crossings come from both halves: the first half's alone are fewer than all.
  const SelfIntersections first = find_self_intersections(V, F.topRows(F.rows() / 2));
  CHECK(first.pairs > 0);
  CHECK(first.pairs < all.pairs);
}
