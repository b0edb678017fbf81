// The fast readers of plain OBJ and OFF (read_plain_text.h): what they take they read exactly as
// the checked OpenMesh path does, and everything else they leave to it (return false).
#include "test_util.h"

#include "libstm/mesh/mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "libstm/mesh/read_plain_text.h"

#include <catch2/catch.hpp>

using sdm::read_plain_obj;
using sdm::read_plain_off;

TEST_CASE("Plain OBJ: positions, polygons, corner forms and negative indices", "[read_plain]") {
  std::vector<Eigen::Vector3d> p;
  std::vector<std::vector<int>> f;
  REQUIRE(read_plain_obj("# a comment\nv 0 0 0\nv 1 0 0\r\nv 0 1 0\nv 0 0 1.5e-3\nvn 0 0 1\ng part\ns off\n"
                         "f 1 2 3\nf 1/1 2/2/2 4//1\nf -4 -2 -1 2\n",
                         p, f));
  REQUIRE(p.size() == 4);
  CHECK(p[3].z() == 1.5e-3);
  REQUIRE(f.size() == 3);
  CHECK(f[0] == std::vector<int>{0, 1, 2});
  CHECK(f[1] == std::vector<int>{0, 1, 3});
  CHECK(f[2] == std::vector<int>{0, 2, 3, 1});
}

TEST_CASE("Plain OBJ: anything else is left to the checked reader", "[read_plain]") {
  std::vector<Eigen::Vector3d> p;
  std::vector<std::vector<int>> f;
  const char* other[] = {
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1 2 3\n",           // uv
      "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",      // a material
      "v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",              // a colour
      "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",                  // NaN
      "v 0 0 1e39\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",                 // beyond float range
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",                    // an index beyond the vertices
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",                    // index 0
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nf /1 2 3\n",                   // a corner without a vertex index
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n",                      // two corners
      "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",                      // two coordinates
      "",                                                        // nothing
  };
  for (const char* text : other) {
    INFO(text);
    CHECK_FALSE(read_plain_obj(text, p, f));
  }
}

TEST_CASE("Plain OFF: counts, comments, polygons; variants are left to the checked reader", "[read_plain]") {
  std::vector<Eigen::Vector3d> p;
  std::vector<std::vector<int>> f;
  REQUIRE(read_plain_off("OFF\n# comment\n4 2 0\n0 0 0\n1 0 0\n0 1 0 # c\n0 0 1\n3 0 1 2\n4 0 1 3 2\n\n", p, f));
  CHECK(p.size() == 4);
  CHECK(f == std::vector<std::vector<int>>{{0, 1, 2}, {0, 1, 3, 2}});
  const char* other[] = {
      "COFF\n3 1 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n3 0 1 2\n",  // colours
      "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 255 0 0\n",                    // a face colour
      "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",                            // fewer faces than counted
      "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n",                   // more
      "OFF\n2000000000 1 0\n0 0 0\n",                                          // a count the file cannot hold
      "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",                            // an index beyond
      "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",                             // counts on the magic line
  };
  for (const char* text : other) {
    INFO(text);
    CHECK_FALSE(read_plain_off(text, p, f));
  }
}

TEST_CASE("A mesh written as OBJ and OFF reads back exactly through the fast readers", "[read_plain]") {
  test_util::TempDir dir;
  const sdm::Mesh m = sdm::make_primitive("bottle");
  for (const char* name : {"m.obj", "m.off"}) {
    sdm::write_mesh(m, dir / name);
    const sdm::MeshSoup soup = sdm::read_mesh_soup(dir / name);
    REQUIRE(soup.points.size() == m.n_vertices());
    REQUIRE(soup.triangles.size() == m.n_faces());
    for (auto v : m.vertices()) CHECK((soup.points[size_t(v.idx())] - sdm::point(m, v)).norm() < 1e-6);  // as precise as written
    for (auto fh : m.faces()) {
      int c = 0;
      for (auto v : m.fv_range(fh)) CHECK(soup.triangles[size_t(fh.idx())][c++] == v.idx());
    }
  }
}
