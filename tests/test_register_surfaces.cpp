// Similarity registration (register_surfaces): a moved, turned, scaled and retessellated copy of a
// model is brought back onto it, with the transform recovered and the surfaces within a fraction of
// an edge; two different shapes stay far apart.
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/primitives.h"
#include "libstm/registration/register_surfaces.h"

#include "synthetic_shapes.h"

#include <catch2/catch.hpp>

#include <cmath>

namespace {

sdm::Mesh transformed(const sdm::Mesh& m, const sdm::Similarity& T) { return synth::moved(m, [&](const Eigen::Vector3d& p) { return T(p); }); }

double angle_between(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180 / M_PI;
}

}  // namespace

TEST_CASE("fit_similarity recovers an exact similarity", "[register_surfaces]") {
  sdm::Similarity T;
  T.scale = 1.7;
  T.rotation = Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  T.translation = {0.3, -4, 2};
  std::vector<Eigen::Vector3d> x{{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3}, {1, 1, 1}}, y;
  for (const auto& p : x) y.push_back(T(p));
  const sdm::Similarity F = sdm::fit_similarity(x, y, std::vector<double>(x.size(), 1.0));
  CHECK(std::abs(F.scale - T.scale) < 1e-12);
  CHECK((F.rotation - T.rotation).norm() < 1e-12);
  CHECK((F.translation - T.translation).norm() < 1e-12);
  const sdm::Similarity I = F.inverse();
  for (const auto& p : x) CHECK((I(F(p)) - p).norm() < 1e-12);
}

TEST_CASE("a moved, turned, scaled and retessellated copy registers back onto its source", "[register_surfaces]") {
  std::string tex;
  sdm::LoadedMesh spot_read = sdm::load_mesh(std::string(SDM_EXAMPLES) + "/spot/spot_triangulated.obj");
  tex = std::move(spot_read.texture);
  const sdm::Mesh spot = std::move(spot_read.mesh);
  // A small turn (found from no rotation) and a large one (from the principal axes).
  const double degrees = GENERATE(15.0, 130.0);
  sdm::Similarity T;
  T.scale = 1.3;
  T.rotation = Eigen::AngleAxisd(degrees * M_PI / 180, Eigen::Vector3d(0.3, 1, 0.2).normalized()).toRotationMatrix();
  T.translation = {0.4, -0.2, 0.7};
  const sdm::Mesh target = transformed(synth::remeshed(spot, 0.9), T);
  REQUIRE(target.n_vertices() != spot.n_vertices());
  const sdm::Registration r = sdm::register_surfaces(spot, target);
  INFO("turned " << degrees << " degrees: RMS " << r.rms << ", p99 " << r.p99 << ", scale " << r.transform.scale << ", rotation off by "
              << angle_between(r.transform.rotation, T.rotation) << " degrees, " << r.iterations << " iterations");
  // Vertices of two tessellations of one curved surface lie off each other's flat triangles by a
  // small fraction of an edge (0.03 of the diagonal here): the residual is that, not misalignment.
  CHECK(r.rms < 0.002);
  CHECK(r.p99 < 0.006);
  CHECK(std::abs(r.transform.scale / T.scale - 1) < 0.003);
  CHECK(angle_between(r.transform.rotation, T.rotation) < 0.3);
  CHECK((r.transform.translation - T.translation).norm() < 0.003 * sdm::bounding_box_diagonal(target));
}

TEST_CASE("different shapes stay far apart after registration", "[register_surfaces]") {
  const sdm::Mesh y = sdm::make_primitive("ypsilon"), x = sdm::make_primitive("crossed-cylinders"), d = sdm::make_primitive("donut");
  for (const auto* t : {&x, &d}) {
    const sdm::Registration r = sdm::register_surfaces(y, *t);
    INFO("RMS " << r.rms << ", p99 " << r.p99);
    CHECK(r.rms > 0.02);
    CHECK(r.p99 > 0.05);
  }
}
