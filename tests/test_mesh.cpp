// Mesh I/O: round trips keep positions and uv; formats are chosen by extension.
#include "libstm/core/errors.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/validate_mesh.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>
#include <cmath>

using namespace sdm;

namespace {

// A regular octahedron with non-trivial coordinates (not representable in float) and
// per-corner uv, so that a lossy reader or writer shows up.
Mesh octahedron_with_uv() {
  Mesh m;
  const double s = 1.0 / 3.0;
  Mesh::VertexHandle v[6] = {
      m.add_vertex({1 + s, 0.1, 0.2}), m.add_vertex({-1 - s, 0.1, 0.2}), m.add_vertex({0, 1 + s, 0.2}),
      m.add_vertex({0, -1 - s, 0.2}),  m.add_vertex({0, 0.1, 1.2 + s}),  m.add_vertex({0, 0.1, -0.8 - s})};
  const int f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  m.request_halfedge_texcoords2D();
  for (int i = 0; i < 8; ++i) {
    auto fh = m.add_face(v[f[i][0]], v[f[i][1]], v[f[i][2]]);
    int c = 0;
    for (auto h : m.fh_range(fh)) {
      m.set_texcoord2D(h, {0.1 * i + 0.01 * c + 1.0 / 7.0, 0.05 * c + 1.0 / 9.0});
      ++c;
    }
  }
  return m;
}

}  // namespace

TEST_CASE("OBJ round trip keeps double positions and per-corner uv and the texture", "[mesh]") {
  test_util::TempDir dir;
  Mesh m = octahedron_with_uv();
  test_util::write_file(dir / "tex.png", "not read here");
  write_mesh(m, dir / "octa.obj", dir / "tex.png");
  std::string texture;
  LoadedMesh r_read = load_mesh(dir / "octa.obj");
  texture = std::move(r_read.texture);
  Mesh r = std::move(r_read.mesh);
  REQUIRE(r.n_vertices() == m.n_vertices());
  REQUIRE(r.n_faces() == m.n_faces());
  for (auto v : m.vertices()) CHECK(((point(m, v) - point(r, r.vertex_handle(v.idx()))).norm() == 0.0));
  REQUIRE(r.has_halfedge_texcoords2D());
  for (auto f : m.faces()) {
    auto rf = r.face_handle(f.idx());
    auto h0 = m.fh_range(f).begin();
    auto h1 = r.fh_range(rf).begin();
    for (int c = 0; c < 3; ++c, ++h0, ++h1) {
      CHECK(m.to_vertex_handle(*h0).idx() == r.to_vertex_handle(*h1).idx());
      CHECK(std::abs(m.texcoord2D(*h0)[0] - r.texcoord2D(*h1)[0]) < 1e-6);  // OpenMesh parses uv as float
      CHECK(std::abs(m.texcoord2D(*h0)[1] - r.texcoord2D(*h1)[1]) < 1e-6);
    }
  }
  CHECK(std::filesystem::equivalent(texture, dir / "tex.png"));
}

TEST_CASE("PLY and OFF and STL round trips keep the surface", "[mesh]") {
  test_util::TempDir dir;
  Mesh m = octahedron_with_uv();
  for (const char* ext : {"ply", "off", "stl"}) {
    const std::string path = dir / (std::string("octa.") + ext);
    write_mesh(m, path);
    Mesh r = load_mesh(path).mesh;
    INFO(ext);
    REQUIRE(r.n_vertices() == 6);
    REQUIRE(r.n_faces() == 8);
    // STL stores triangles only, so vertex order may change: compare as point sets.
    for (auto v : m.vertices()) {
      double best = 1e9;
      for (auto w : r.vertices()) best = std::min(best, (point(m, v) - point(r, w)).norm());
      CHECK(best < 1e-6);  // binary PLY and STL store single precision
    }
    CHECK(std::abs(bounding_box_diagonal(r) - bounding_box_diagonal(m)) < 1e-6);
  }
}

TEST_CASE("Writing to a missing folder or an unknown format fails cleanly", "[mesh]") {
  test_util::TempDir dir;
  Mesh m = octahedron_with_uv();
  CHECK_THROWS_AS(write_mesh(m, dir / "no/such/dir/a.obj"), InputError);
  CHECK_THROWS_AS(write_mesh(m, dir / "a.xyz"), InputError);
  const auto left = std::distance(std::filesystem::directory_iterator(dir.path), std::filesystem::directory_iterator());
  CHECK(left == 0);
}

TEST_CASE("Spot reads with its uv and texture from the MTL", "[mesh]") {
  std::string texture;
  LoadedMesh spot_read = load_mesh(std::string(SDM_EXAMPLES) + "/spot/spot_triangulated.obj");
  texture = std::move(spot_read.texture);
  Mesh spot = std::move(spot_read.mesh);
  CHECK(spot.n_vertices() == 2930);
  CHECK(spot.n_faces() == 5856);
  CHECK(spot.has_halfedge_texcoords2D());
  CHECK(texture.size() > 0);
  CHECK(std::filesystem::exists(texture));
}
