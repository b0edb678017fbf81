// A model far from the origin goes through the pipeline as it does at the origin: the stages work
// on it moved to its centre and give their results back in the input's frame. Spot (examples/data)
// moved +1e3, +1e4 and +1e6 in x keeps its skeleton's branching, its skeleton lands where the
// origin's lands moved by the same offset, and its round trip's RMS stays within 1.2 times the
// origin's (the decoded mesh is compared with the moved input, so it is in the input's frame).
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/skeleton.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

using test_util::run_sdm;

namespace {

struct FarRun {
  nlohmann::json skeleton, roundtrip;
  sdm::Skeleton nodes;
};

// Spot with its coordinates on a grid of 2^-20 model units (at most 1e-6 of its diagonal away), so
// that moving it by up to 1e6 is exact in double: the far copies hold the same shape to the last
// bit, and any difference in the results comes from where the model lies, not from its file.
sdm::Mesh on_grid(sdm::Mesh mesh) {
  for (auto v : mesh.vertices())
    for (int k = 0; k < 3; ++k) mesh.point(v)[k] = std::ldexp(std::round(std::ldexp(mesh.point(v)[k], 20)), -20);
  return mesh;
}

FarRun run_at(const sdm::Mesh& spot, double offset, const test_util::TempDir& dir) {
  sdm::Mesh moved = spot;
  for (auto v : moved.vertices()) moved.point(v)[0] += offset;
  const std::string name = "spot_" + std::to_string(int64_t(offset));
  sdm::write_mesh(moved, dir / (name + ".obj"));
  FarRun out;
  const test_util::RunResult s = run_sdm("skeleton " + dir / (name + ".obj") + " -o " + dir / (name + ".json") + " --json");
  INFO(s.output);
  REQUIRE(s.exit_code == 0);
  out.skeleton = test_util::last_json(s);
  out.nodes = sdm::read_skeleton_json(dir / (name + ".json"));
  const test_util::RunResult r = run_sdm("roundtrip " + dir / (name + ".obj") + " --size 512 --samples 20000 --json");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  out.roundtrip = test_util::last_json(r);
  return out;
}

}  // namespace

TEST_CASE("Spot far from the origin keeps its skeleton and its round trip's error", "[far_from_origin][skeleton][roundtrip]") {
  const sdm::Mesh spot = on_grid(sdm::load_mesh(std::string(SDM_EXAMPLES) + "/spot/spot_triangulated.obj").mesh);
  const double diag = sdm::bounding_box_diagonal(spot);
  test_util::TempDir dir;
  const FarRun origin = run_at(spot, 0, dir);
  const double rms0 = origin.roundtrip.at("rms").get<double>();
  CHECK(origin.skeleton.at("end_nodes").get<int>() >= 5);  // four legs and the head at least
  for (double offset : {1e3, 1e4, 1e6}) {
    INFO("offset " << offset);
    const FarRun far = run_at(spot, offset, dir);
    for (const char* count : {"nodes", "edges", "branch_nodes", "end_nodes", "cycles"})
      CHECK(far.skeleton.at(count) == origin.skeleton.at(count));
    // The same nodes, moved by the offset: within float noise of the model's size.
    REQUIRE(far.nodes.nodes.size() == origin.nodes.nodes.size());
    double moved = 0;
    for (size_t n = 0; n < far.nodes.nodes.size(); ++n)
      moved = std::max(moved, (far.nodes.nodes[n] - Eigen::Vector3d(offset, 0, 0) - origin.nodes.nodes[n]).norm());
    CHECK(moved < 1e-6 * diag);
    CHECK(far.roundtrip.at("segments") == origin.roundtrip.at("segments"));
    const double rms = far.roundtrip.at("rms").get<double>();
    CHECK(rms <= 1.2 * rms0);
  }
}
