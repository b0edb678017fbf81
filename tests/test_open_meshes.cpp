// Open meshes go through the pipeline: the skeleton is extracted with the holes filled,
// the output keeps the holes (same number of boundary loops), `--fill-holes` closes them instead.
// Inputs: a capsule with a hole cut into each cap and one into its side (three loops; the analytic
// surface x^2 + y^2 = 1, |z| <= 1, with hemispheres, tells whether the skeleton lies inside), and
// the open CAD part of ../shared/models/cgal (four loops).
#include "faust_pairs.h"
#include "test_util.h"

#include "libstm/mesh/fill_holes.h"
#include "libstm/mesh/inside_mesh.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "libstm/mesh/validate_mesh.h"
#include "libstm/skeleton/extract_skeleton.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

// Measured 2026-11-26 (Release): the open capsule at 512, level 3, RMS 0.0039 % and Hausdorff
// 0.10 % of the diagonal; the CAD part at 1024 RMS 0.060 % and Hausdorff 2.5 % (its sharp edges, as
// on the closed CAD parts). The thresholds hold these with a margin.
constexpr double kOpenRms = 0.0002, kOpenHausdorff = 0.005, kSharkRms = 0.001, kSharkHausdorff = 0.04;

namespace {

// `m` without the faces whose centroid lies within `r` of one of `centres`: a hole around each,
// the vertices left in their order (as a tool deleting faces and loose vertices leaves them).
// `kept`, when given, receives per vertex of the result its index in m.
sdm::Mesh cut_holes(const sdm::Mesh& m, const std::vector<Eigen::Vector3d>& centres, double r, std::vector<int>* kept = nullptr) {
  std::vector<std::array<int, 3>> faces;
  std::vector<int> index(m.n_vertices(), -1);
  for (auto f : m.faces()) {
    std::array<int, 3> t{};
    int c = 0;
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (auto v : m.fv_range(f)) t[c++] = v.idx(), g += sdm::point(m, v) / 3;
    bool cut = false;
    for (const auto& x : centres) cut = cut || (g - x).norm() < r;
    if (cut) continue;
    for (int v : t) index[v] = 0;
    faces.push_back(t);
  }
  sdm::MeshSoup soup;
  if (kept) kept->clear();
  for (auto v : m.vertices())
    if (index[v.idx()] == 0) {
      index[v.idx()] = int(soup.points.size());
      soup.points.push_back(sdm::point(m, v));
      if (kept) kept->push_back(v.idx());
    }
  for (auto& t : faces) soup.triangles.push_back({index[t[0]], index[t[1]], index[t[2]]});
  return sdm::build_mesh(soup);
}

// The capsule (axis z, radius 1, length 4) with a hole of radius r around each of `centres`.
sdm::Mesh capsule_with_holes(const std::vector<Eigen::Vector3d>& centres, double r) {
  return cut_holes(sdm::make_primitive("capsule", 3000), centres, r);
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
  const sdm::MeshReport back = sdm::validate_mesh(sdm::mesh_to_soup(sdm::load_mesh(dir / "back.ply").mesh));
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

namespace {

// Per line of a correspondence file (source face, barycentric coordinates), the distance of the
// source point from source vertex truth[j], in % of the source's diagonal: mean and 90th percentile.
std::pair<double, double> correspondence_error(const sdm::Mesh& source, const std::string& path, const std::vector<int>& truth) {
  std::ifstream in(path);
  std::string line;
  std::vector<double> e;
  const double diag = sdm::bounding_box_diagonal(source);
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream l(line);
    int f = 0;
    double b[3] = {0, 0, 0};
    l >> f >> b[0] >> b[1] >> b[2];
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    int c = 0;
    for (auto v : source.fv_range(source.face_handle(f))) p += b[c++] * sdm::point(source, v);
    e.push_back(100 * (p - sdm::point(source, source.vertex_handle(truth[e.size()]))).norm() / diag);
  }
  if (e.size() != truth.size()) return {INFINITY, INFINITY};
  double mean = 0;
  for (double x : e) mean += x / double(e.size());
  std::sort(e.begin(), e.end());
  return {mean, e[size_t(0.9 * double(e.size()))]};
}

}  // namespace

// Transfer onto open targets: FAUST 007 (textured) onto 007 and onto 024 with three holes each (at
// a hip, a foot and a hand; 2 % of the diagonal). The capped surfaces' Euler characteristic is the
// source's, so 007 is carried and 024 registered as another body. Measured 2026-11-26: carried
// 0.002 % mean; registered 2.86 %, p90 6.1 % (the closed 024: 2.04 %, 4.2 %; the same holes with the
// vertices numbered otherwise gave 2.03-2.93 %: the extraction still depends on the vertex order,
// DECISIONS 1, "Open meshes"). The thresholds hold today's accuracy between bodies.
TEST_CASE("sdm transfer onto FAUST bodies with holes", "[open_mesh]") {
  if (!faust::have("tr_reg_007.off") || !faust::have("tr_reg_024.off")) {
    WARN("no FAUST meshes at " << faust::humans_dir() << ": skipped");
    return;
  }
  test_util::TempDir dir;
  const sdm::Mesh a = faust::write_textured("tr_reg_007.off", dir / "a.obj", dir / "a.png");
  const std::vector<int> at{1933, 3353, 5876};
  for (const char* name : {"tr_reg_007.off", "tr_reg_024.off"}) {
    const sdm::Mesh full = sdm::load_mesh(faust::humans_dir() + "/" + name).mesh;
    std::vector<int> kept;
    std::vector<Eigen::Vector3d> centres;
    for (int v : at) centres.push_back(sdm::point(full, full.vertex_handle(v)));
    const sdm::Mesh open = cut_holes(full, centres, 0.02 * sdm::bounding_box_diagonal(full), &kept);
    REQUIRE(sdm::validate_mesh(sdm::mesh_to_soup(open)).boundary_loops >= 3);  // a cut across fingers makes more
    sdm::write_mesh(open, dir / "open.off");
    const auto r = test_util::run_sdm("transfer --source " + (dir / "a.obj") + " --target " + (dir / "open.off") + " -o " + (dir / "b.obj") +
                                      " --size 256 --correspondence " + (dir / "c.txt") + " --json");
    INFO(name << ": " << r.output);
    REQUIRE(r.exit_code == 0);
    const auto j = json_of(r);
    const auto [mean, p90] = correspondence_error(a, dir / "c.txt", kept);
    std::fprintf(stderr, "007 onto %s with 3 holes: %s, correspondence mean %.3f %%, p90 %.3f %%\n", name,
                 j.at("target_skeleton").get<std::string>().c_str(), mean, p90);
    if (std::string(name) == "tr_reg_007.off") {
      CHECK(j.at("target_skeleton") == "carried");
      CHECK(mean < 0.05);
    } else {
      CHECK(j.at("target_skeleton") == "registered");
      CHECK(mean < 3.5);
      CHECK(p90 < 7.5);
    }
  }
}

// A scan-like stand-in: bunny00 of ../shared with five holes (3 % of the diagonal around five spread
// vertices), through the whole command at the round-trip table's setting (map 1024, level 3). Measured
// 2026-11-26: RMS 0.0166 %, Hausdorff 0.76 % (the closed bunny00: 0.015 %, 0.76 %), 5 loops out;
// skeleton without cycles or edges outside. The same mesh with its vertices numbered in the order
// the faces use them gave 0.022 % and 1.68 %, written with 9 digits 0.0167 % and 0.885 %: the
// outcome still depends on the numbering and the last digits.
TEST_CASE("bunny00 with five holes round-trips within the real meshes' bounds with its five loops", "[open_mesh]") {
  const std::string path = faust::humans_dir() + "/../cgal/bunny00.off";
  if (!std::filesystem::exists(path)) {
    WARN("no " << path << ": skipped");
    return;
  }
  test_util::TempDir dir;
  const sdm::Mesh full = sdm::load_mesh(path).mesh;
  std::vector<Eigen::Vector3d> centres;
  for (int v : {8805, 37023, 5053, 7739, 16900}) centres.push_back(sdm::point(full, full.vertex_handle(v)));
  const sdm::Mesh open = cut_holes(full, centres, 0.03 * sdm::bounding_box_diagonal(full));
  REQUIRE(sdm::validate_mesh(sdm::mesh_to_soup(open)).boundary_loops == 5);
  sdm::write_mesh(open, dir / "bunny_holes.off");
  const auto sk = test_util::run_sdm("skeleton " + (dir / "bunny_holes.off") + " -o " + (dir / "s.json") + " --json");
  REQUIRE(sk.exit_code == 0);
  const auto s = json_of(sk);
  CHECK(s.at("filled_loops") == 5);
  CHECK(s.at("cycles") == 0);
  CHECK(s.at("outside_edges") == 0);
  const auto r = test_util::run_sdm("roundtrip " + (dir / "bunny_holes.off") + " --size 1024 --lod 3 --json");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto j = json_of(r);
  std::fprintf(stderr, "bunny00 with 5 holes: RMS %g, Hausdorff %g\n", j.at("rms").get<double>(), j.at("hausdorff").get<double>());
  CHECK(j.at("manifold") == true);
  CHECK(j.at("boundary_loops") == 5);
  CHECK(j.at("rms").get<double>() < 0.0005);
  CHECK(j.at("hausdorff").get<double>() < 0.01);
}
