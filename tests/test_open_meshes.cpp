// Open meshes go through the pipeline (issue 16): the skeleton is extracted with the holes filled,
// the output keeps the holes (same number of boundary loops), `--fill-holes` closes them instead.
// Inputs: a capsule with a hole cut into each cap and one into its side (three loops; the analytic
// surface x^2 + y^2 = 1, |z| <= 1, with hemispheres, tells whether the skeleton lies inside), and
// the open CAD part of ../shared/models/cgal (four loops).
#include "faust_pairs.h"
#include "test_util.h"

#include "libstm/mesh/fill_holes.h"
#include "libstm/mesh/inside_mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "libstm/mesh/validate_mesh.h"
#include "libstm/skeleton/extract_skeleton.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>

// Measured 2026-11-26 (Release): the open capsule at 512, level 3, RMS 0.0039 % and Hausdorff
// 0.10 % of the diagonal; the CAD part at 1024 RMS 0.060 % and Hausdorff 2.5 % (its sharp edges, as
// on the closed CAD parts: issue 17). The thresholds hold these with a margin.
constexpr double kOpenRms = 0.0002, kOpenHausdorff = 0.005, kSharkRms = 0.001, kSharkHausdorff = 0.04;

namespace {

// The capsule (axis z, radius 1, length 4) without the faces whose centroid lies within `r` of
// each of `centres`: one hole per centre.
sdm::Mesh capsule_with_holes(const std::vector<Eigen::Vector3d>& centres, double r) {
  const sdm::Mesh closed = sdm::make_primitive("capsule", 3000);
  sdm::MeshSoup soup;
  std::vector<int> index(closed.n_vertices(), -1);
  for (auto f : closed.faces()) {
    std::array<int, 3> t{};
    int c = 0;
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    for (auto v : closed.fv_range(f)) t[c++] = v.idx(), m += sdm::point(closed, v) / 3;
    bool cut = false;
    for (const auto& x : centres) cut = cut || (m - x).norm() < r;
    if (cut) continue;
    for (int& v : t) {
      if (index[v] < 0) index[v] = int(soup.points.size()), soup.points.push_back(sdm::point(closed, closed.vertex_handle(v)));
      v = index[v];
    }
    soup.triangles.push_back(t);
  }
  return sdm::build_mesh(soup);
}

const std::vector<Eigen::Vector3d> kHoles{{0, 0, 2}, {0, 0, -2}, {1, 0, 0}};

nlohmann::json json_of(const test_util::RunResult& r) { return nlohmann::json::parse(r.output.substr(r.output.find("{\n"))); }

}  // namespace

TEST_CASE("An open mesh is read with its holes and its genus once capped", "[open_mesh]") {
  const sdm::Mesh m = capsule_with_holes(kHoles, 0.35);
  const sdm::MeshReport r = sdm::validate_mesh(sdm::mesh_to_soup(m));
  CHECK(r.usable());
  CHECK(r.boundary_loops == 3);
  CHECK(r.genus_per_part == std::vector<int>{0});
  const sdm::Mesh filled = sdm::fill_holes(m);
  const sdm::MeshReport f = sdm::validate_mesh(sdm::mesh_to_soup(filled));
  CHECK(f.usable());
  CHECK(f.boundary_loops == 0);
  CHECK(f.genus_per_part == std::vector<int>{0});
}

TEST_CASE("The skeleton of an open mesh lies on the capsule's axis and maps the input's vertices only", "[open_mesh]") {
  const sdm::Mesh m = capsule_with_holes(kHoles, 0.35);
  sdm::SkeletonStats st;
  const sdm::Skeleton s = sdm::extract_skeleton(m, {}, {}, &st);
  CHECK(st.filled_loops == 3);
  CHECK(st.fill_vertices > 0);
  REQUIRE(s.vertex_node.size() == m.n_vertices());
  for (int n : s.vertex_node) REQUIRE((n >= 0 && n < int(s.nodes.size())));
  CHECK(s.cycles() == 0);
  CHECK(s.end_nodes() == 2);
  // Every node within a tenth of the radius of the axis, inside the closed capsule's length.
  for (const auto& p : s.nodes) {
    CHECK(std::hypot(p.x(), p.y()) < 0.1);
    CHECK(std::abs(p.z()) < 2.0);
  }
}

TEST_CASE("sdm roundtrip keeps an open mesh's holes; --fill-holes closes them", "[open_mesh]") {
  test_util::TempDir dir;
  const sdm::Mesh m = capsule_with_holes(kHoles, 0.35);
  sdm::write_mesh(m, dir / "open.off");
  const auto kept = test_util::run_sdm("roundtrip " + (dir / "open.off") + " --size 512 --lod 3 --json");
  INFO(kept.output);
  REQUIRE(kept.exit_code == 0);
  const auto j = json_of(kept);
  std::fprintf(stderr, "open capsule: RMS %g, Hausdorff %g\n", j.at("rms").get<double>(), j.at("hausdorff").get<double>());
  CHECK(j.at("manifold") == true);
  CHECK(j.at("closed") == false);
  CHECK(j.at("input_boundary_loops") == 3);
  CHECK(j.at("boundary_loops") == 3);
  CHECK(j.at("rms").get<double>() < kOpenRms);
  CHECK(j.at("hausdorff").get<double>() < kOpenHausdorff);
  const auto filled = test_util::run_sdm("roundtrip " + (dir / "open.off") + " --size 512 --lod 3 --fill-holes --json");
  INFO(filled.output);
  REQUIRE(filled.exit_code == 0);
  const auto k = json_of(filled);
  CHECK(k.at("closed") == true);
  CHECK(k.at("boundary_loops") == 0);
  CHECK(filled.output.find("--fill-holes: closed 3 hole(s)") != std::string::npos);
  // Decoding the written map rebuilds the same three loops.
  REQUIRE(test_util::run_sdm("encode " + (dir / "open.off") + " -o " + (dir / "open.exr") + " --size 512").exit_code == 0);
  const auto dec = test_util::run_sdm("decode " + (dir / "open.exr") + " -o " + (dir / "back.ply") + " --lod 2 --json");
  INFO(dec.output);
  REQUIRE(dec.exit_code == 0);
  CHECK(json_of(dec).at("boundary_loops") == 3);
  const sdm::MeshReport back = sdm::validate_mesh(sdm::mesh_to_soup(sdm::load_mesh(dir / "back.ply")));
  CHECK(back.boundary_loops == 3);
  CHECK(back.usable());
}

TEST_CASE("The open CAD part of ../shared round-trips with its four holes", "[open_mesh]") {
  const std::string path = faust::humans_dir() + "/../cgal/mech-holes-shark.off";
  if (!std::filesystem::exists(path)) {
    WARN("no " << path << ": skipped");
    return;
  }
  const auto r = test_util::run_sdm("roundtrip " + path + " --size 1024 --lod 3 --json");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto j = json_of(r);
  std::fprintf(stderr, "shark: RMS %g, Hausdorff %g\n", j.at("rms").get<double>(), j.at("hausdorff").get<double>());
  CHECK(j.at("manifold") == true);
  CHECK(j.at("input_boundary_loops") == 4);
  CHECK(j.at("boundary_loops") == 4);
  CHECK(j.at("rms").get<double>() < kSharkRms);
  CHECK(j.at("hausdorff").get<double>() < kSharkHausdorff);
}
