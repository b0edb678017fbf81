// Mesh files keep the coordinates they were given (write_positions.h): text OFF, OBJ and PLY read
// back bitwise equal through `sdm convert`, whatever digits the input had; STL and glTF, which hold
// float32, say what rounding cost when the model lies far from the origin for its size.
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/write_positions.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>
#include <algorithm>
#include <charconv>
#include <cstdio>
#include <string>
#include <vector>

using test_util::run_sdm;

namespace {

// A tetrahedron far from the origin, its coordinates with more digits than float keeps.
const std::vector<Eigen::Vector3d> kCorners = {{1000000.317288, 2.0000000000000004, -3e-7},
                                                {1000001.1234567891, 0.1, 0.3},
                                                {1000000.5, 1.0 / 3.0, 0.7000000000000001},
                                                {1000000.7777777777, 0.6, -0.123456789012345678}};
const int kFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};

std::string number(double x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

std::string ascii_ply() {
  std::string s = "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
                  "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : kCorners) s += number(p.x()) + " " + number(p.y()) + " " + number(p.z()) + "\n";
  for (const auto& f : kFaces) s += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
  return s;
}

// Every point of `path` equals its corner to the last bit (the file keeps the vertex order).
void require_exact(const std::string& path) {
  const sdm::MeshSoup soup = sdm::read_mesh_soup(path);
  REQUIRE(soup.points.size() == kCorners.size());
  for (size_t i = 0; i < kCorners.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      INFO(path << " vertex " << i << " coordinate " << k << ": " << number(soup.points[i][k]) << " for " << number(kCorners[i][k]));
      CHECK(soup.points[i][k] == kCorners[i][k]);
    }
}

}  // namespace

TEST_CASE("convert keeps every coordinate of a text mesh in OFF, OBJ and PLY", "[write_positions][convert]") {
  test_util::TempDir dir;
  test_util::write_file(dir / "in.ply", ascii_ply());
  require_exact(dir / "in.ply");  // the reader keeps them too
  std::string from = dir / "in.ply";
  // A chain through every format that keeps doubles, back to the first.
  for (const char* name : {"a.off", "b.obj", "c.ply", "d.off"}) {
    const test_util::RunResult r = run_sdm("convert " + from + " -o " + dir / name + " --no-repair");
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    CHECK(r.output.find("warning") == std::string::npos);
    require_exact(dir / name);
    from = dir / name;
  }
}

TEST_CASE("PLY is written in float while float keeps every coordinate, in double otherwise", "[write_positions]") {
  sdm::Mesh mesh;
  std::vector<sdm::Mesh::VertexHandle> v;
  for (const auto& p : kCorners) v.push_back(mesh.add_vertex({double(float(p.x())), double(float(p.y())), double(float(p.z()))}));
  for (const auto& f : kFaces) mesh.add_face(v[size_t(f[0])], v[size_t(f[1])], v[size_t(f[2])]);
  CHECK(sdm::ply_bytes(mesh).find("property float x") != std::string::npos);
  CHECK(sdm::float32_rounding(mesh) == 0);
  mesh.set_point(v[0], {kCorners[0].x(), kCorners[0].y(), kCorners[0].z()});
  CHECK(sdm::ply_bytes(mesh).find("property double x") != std::string::npos);
  // Only corner 0 moves, 1000000.317288 to 1000000.3125 in x and its y, z to their floats.
  const Eigen::Vector3d p = kCorners[0];
  CHECK(sdm::float32_rounding(mesh) == Approx((p - p.cast<float>().cast<double>()).norm() / sdm::bounding_box_diagonal(mesh)).epsilon(1e-9));
}

TEST_CASE("STL and glTF say what float32 costs a model far from the origin", "[write_positions][convert]") {
  test_util::TempDir dir;
  test_util::write_file(dir / "far.ply", ascii_ply());
  for (const char* name : {"far.stl", "far.glb"}) {
    const test_util::RunResult r = run_sdm("convert " + dir / "far.ply" + " -o " + dir / name + " --json");
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    CHECK(r.output.find("warning: " + dir / name + " holds 32-bit floats") != std::string::npos);
    // The corner float moves farthest, over the tetrahedron's diagonal.
    Eigen::Vector3d lo = kCorners[0], hi = kCorners[0];
    double worst = 0;
    for (const auto& p : kCorners) {
      lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
      worst = std::max(worst, (p - p.cast<float>().cast<double>()).norm());
    }
    CHECK(test_util::last_json(r).at("float32_rounding").get<double>() == Approx(worst / (hi - lo).norm()).epsilon(1e-9));
  }
  // Near the origin the same tetrahedron loses under 1e-7 of its diagonal: no warning.
  std::string near = ascii_ply();
  for (size_t at = near.find("100000"); at != std::string::npos; at = near.find("100000", at)) near.replace(at, 6, "");
  test_util::write_file(dir / "near.ply", near);
  const test_util::RunResult r = run_sdm("convert " + dir / "near.ply" + " -o " + dir / "near.stl --json");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("warning") == std::string::npos);
  CHECK(test_util::last_json(r).at("float32_rounding").get<double>() < 1e-6);
}
