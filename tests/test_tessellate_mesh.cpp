// Tessellation with a rate per face: watertight and manifold whatever the mix of rates.
#include "libsdm/decode/tessellate_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/validate_mesh.h"

#include <catch2/catch.hpp>

using namespace sdm;

namespace {

// Icosahedron: a closed genus-0 base with 20 faces.
void icosahedron(Eigen::MatrixX3d& V, Eigen::MatrixX3i& F) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  V.resize(12, 3);
  V << -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1, -t, 0, -1, -t, 0, 1;
  F.resize(20, 3);
  F << 0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3,
      2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1;
}

MeshReport check(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Tessellation& t) {
  MeshSoup soup;
  for (size_t i = 0; i < t.point_face.size(); ++i) {
    const int f = t.point_face[i];
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c) p += t.point_bary[i][c] * V.row(F(f, c)).transpose();
    soup.points.push_back(p);
  }
  for (int r = 0; r < t.triangles.rows(); ++r) soup.triangles.push_back({t.triangles(r, 0), t.triangles(r, 1), t.triangles(r, 2)});
  return validate_mesh(soup);
}

}  // namespace

TEST_CASE("Uniform rate r gives r squared triangles per face and a closed manifold", "[tessellate_mesh]") {
  Eigen::MatrixX3d V;
  Eigen::MatrixX3i F;
  icosahedron(V, F);
  for (int r : {1, 2, 5, 8}) {
    Tessellation t = tessellate_mesh(F, std::vector<int>(20, r));
    CHECK(t.triangles.rows() == 20 * r * r);
    // Euler: V - E + F = 2 with E = 3F/2 -> V = F/2 + 2.
    CHECK(long(t.point_face.size()) == 10L * r * r + 2);
    MeshReport rep = check(V, F, t);
    CHECK(rep.usable());
    CHECK(rep.genus_per_part == std::vector<int>{0});
  }
}

TEST_CASE("Mixed rates stay watertight with no degenerate triangles", "[tessellate_mesh]") {
  Eigen::MatrixX3d V;
  Eigen::MatrixX3i F;
  icosahedron(V, F);
  std::vector<int> rate(20);
  for (int f = 0; f < 20; ++f) rate[f] = 1 << (f % 5);  // levels 0 to 4 side by side
  Tessellation t = tessellate_mesh(F, rate);
  MeshReport rep = check(V, F, t);
  INFO(rep.refusal("tessellation"));
  CHECK(rep.usable());
  CHECK(rep.findings.empty());
  CHECK(rep.genus_per_part == std::vector<int>{0});
  for (size_t i = 0; i < t.point_bary.size(); ++i) {
    CHECK(t.point_bary[i].minCoeff() >= -1e-12);
    CHECK(t.point_bary[i].sum() == Approx(1.0));
  }
}
