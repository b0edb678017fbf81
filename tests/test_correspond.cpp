// `sdm correspond` and correspond() (libstm/correspondence/correspond, DECISIONS 5): the transfer's
// dense correspondence without a texture or GL. A new tessellation of the ypsilon gets, per vertex,
// a point of the source on the surface under it; a bent and thickened ypsilon gets its points on the
// same branch; a target of another branching is refused with nothing written.
#include "libstm/correspondence/correspond.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/transfer/transfer_texture.h"
#include "synthetic_shapes.h"
#include "test_util.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace {

// Per line of a correspondence file, the source point's position.
std::vector<Eigen::Vector3d> read_points(const std::string& path, const sdm::Mesh& source) {
  std::ifstream in(path);
  std::vector<Eigen::Vector3d> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    sdm::SourcePoint p;
    s >> p.face >> p.barycentric[0] >> p.barycentric[1] >> p.barycentric[2];
    out.push_back(sdm::position_of(source, p));
  }
  return out;
}

}  // namespace

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
  const std::vector<Eigen::Vector3d> at = read_points(dir / "c.txt", a);
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
