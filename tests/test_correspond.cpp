// `sdm correspond` and correspond() (libstm/correspondence/correspond, DECISIONS 5): the transfer's
// dense correspondence without a texture or GL. A new tessellation of the ypsilon gets, per vertex,
// a point of the source on the surface under it; a bent and thickened ypsilon gets its points on the
// same branch; a target of another branching is refused with nothing written, also where the other
// extraction candidates cannot be extracted; recognised_kind takes no NaN for a fit.
#include "libstm/core/errors.h"
#include "libstm/correspondence/correspond.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/transfer/transfer_texture.h"
#include "correspondence_points.h"
#include "synthetic_shapes.h"
#include "test_util.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

TEST_CASE("correspond onto a new tessellation of the ypsilon carries the skeleton and lays every point under its vertex", "[correspond]") {
  const sdm::Mesh a = sdm::make_primitive("ypsilon", 1200);
  const sdm::Mesh b = synth::remeshed(a, 0.8);
  const sdm::SkeletonOptions so = sdm::transfer_skeleton_options();
  const sdm::Correspondence c = sdm::correspond(a, sdm::extract_skeleton(a, so), b, sdm::extract_skeleton(b, so));
  CHECK(c.kind == sdm::CorrespondenceKind::carried);
  REQUIRE(c.points.size() == b.n_vertices());
  CHECK(c.face_points.size() == b.n_faces());
  double worst = 0;
  for (auto v : b.vertices()) worst = std::max(worst, (sdm::position_of(a, c.points[size_t(v.idx())]) - sdm::point(b, v)).norm());
  WARN("farthest source point: " << 100 * worst / sdm::bounding_box_diagonal(b) << " % of the diagonal");
  CHECK(worst < 0.01 * sdm::bounding_box_diagonal(b));
}

TEST_CASE("sdm correspond writes one source point per target vertex, and refuses another branching writing nothing", "[correspond]") {
  test_util::TempDir dir;
  const sdm::Mesh a = sdm::make_primitive("ypsilon", 1200);
  const sdm::Mesh b = synth::remeshed(a, 0.8);
  sdm::write_mesh(a, dir / "a.off");
  sdm::write_mesh(b, dir / "b.off");
  auto res = test_util::run_sdm("correspond " + (dir / "a.off") + " " + (dir / "b.off") + " -o " + (dir / "c.txt") + " --json");
  INFO(res.output);
  REQUIRE(res.exit_code == 0);
  const nlohmann::json j = test_util::last_json(res);
  CHECK(j["kind"] == "carried");
  CHECK(j["target_vertices"] == b.n_vertices());
  const std::vector<Eigen::Vector3d> at = test_util::read_points(dir / "c.txt", a);
  REQUIRE(at.size() == b.n_vertices());
  double worst = 0;
  for (auto v : b.vertices()) worst = std::max(worst, (at[size_t(v.idx())] - sdm::point(b, v)).norm());
  CHECK(worst < 0.01 * sdm::bounding_box_diagonal(b));
  // Another branching: exit 2, naming what differs, nothing written.
  sdm::write_mesh(sdm::make_primitive("crossed-cylinders", 1200), dir / "x.off");
  res = test_util::run_sdm("correspond " + (dir / "a.off") + " " + (dir / "x.off") + " -o " + (dir / "d.txt"));
  INFO(res.output);
  CHECK(res.exit_code == 2);
  CHECK(res.output.find("branchings differ") != std::string::npos);
  CHECK(!std::filesystem::exists(dir / "d.txt"));
  // A wrong output kind: exit 2 before any work.
  res = test_util::run_sdm("correspond " + (dir / "a.off") + " " + (dir / "b.off") + " -o " + (dir / "c.obj"));
  CHECK(res.exit_code == 2);
  CHECK(res.output.find(".txt or .json") != std::string::npos);
}

TEST_CASE("recognised_kind: a measure that is not a number makes the target neither carried nor bent", "[correspond]") {
  const sdm::CorrespondOptions opt;
  sdm::Registration moved;
  moved.rms = 0.008, moved.p99 = 0.015;  // under twice same_shape_rms: the same shape if bending explains little
  sdm::SkeletonFit bent;
  bent.rms = 0.007, bent.p99 = 0.02, bent.end_spread = 1;  // 0.008 <= 1.5 x 0.007: carried
  CHECK(sdm::recognised_kind(moved, &bent, opt) == sdm::CorrespondenceKind::carried);
  CHECK(sdm::recognised_kind(moved, nullptr, opt) == sdm::CorrespondenceKind::skeleton_only);  // not bent yet
  bent.rms = NAN;  // 0.008 <= 1.5 x NaN fails: not the same shape, nor bent
  CHECK(sdm::recognised_kind(moved, &bent, opt) == sdm::CorrespondenceKind::skeleton_only);
  moved.rms = NAN, bent.rms = 0.003, bent.p99 = 0.01;  // a close bent fit stands without the moved one
  CHECK(sdm::recognised_kind(moved, &bent, opt) == sdm::CorrespondenceKind::bent);
  bent.p99 = NAN;
  CHECK(sdm::recognised_kind(moved, &bent, opt) == sdm::CorrespondenceKind::skeleton_only);
  moved.rms = 0.004, moved.p99 = 0.01;  // within same_shape_rms and same_shape_p99: carried whatever the bent fit
  CHECK(sdm::recognised_kind(moved, &bent, opt) == sdm::CorrespondenceKind::carried);
}

TEST_CASE("an other extraction candidate that cannot be extracted leaves the given skeletons' refusal", "[correspond]") {
  // The ypsilon (three ends) onto the crossed cylinders (four), both of genus 0: the branchings
  // differ, so each model's other candidate is asked for; its extraction failing is no candidate.
  const sdm::Mesh a = sdm::make_primitive("ypsilon", 1200), b = sdm::make_primitive("crossed-cylinders", 1200);
  const sdm::SkeletonOptions so = sdm::transfer_skeleton_options();
  sdm::CorrespondOptions opt;
  int asked = 0;
  opt.other_candidate = [&](bool) -> std::optional<sdm::Skeleton> {
    ++asked;
    throw sdm::InputError("no other candidate here");
  };
  try {
    sdm::correspond(a, sdm::extract_skeleton(a, so), b, sdm::extract_skeleton(b, so), opt);
    FAIL("another branching was taken");
  } catch (const sdm::InputError& e) {
    INFO(e.what());
    CHECK(std::string(e.what()).find("branchings differ") != std::string::npos);
    CHECK(std::string(e.what()).find("no other candidate here") == std::string::npos);
  }
  CHECK(asked == 2);  // the source's and the target's, each once
}
