// The fast reader of binary PLY (read_binary_ply.h): what it takes it reads as the written file
// holds it (positions in the file's precision, colours, polygons, either byte order), and
// everything else it leaves to the checked OpenMesh path (returns false), whose messages stay.
#include "test_util.h"

#include "libstm/core/errors.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "libstm/mesh/read_binary_ply.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <catch2/catch.hpp>
#include <cstring>
#include <fstream>

using sdm::BinaryPly;
using sdm::read_binary_ply;

namespace {

// Appends v in big-endian byte order.
template <class T>
void put_big(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  for (size_t i = 0; i < sizeof(T); ++i) s.push_back(b[sizeof(T) - 1 - i]);
}

// A unit square as two triangles and a quad pyramid tip, big-endian, double positions, normals
// (skipped) and byte colours: every path of the reader but little-endian.
std::string big_endian_ply(int faces_announced) {
  std::string s =
      "ply\nformat binary_big_endian 1.0\ncomment made by hand\nelement vertex 5\nproperty double x\nproperty double y\n"
      "property double z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nproperty uchar green\n"
      "property uchar blue\nproperty uchar alpha\nelement face " +
      std::to_string(faces_announced) + "\nproperty list uchar int vertex_indices\nend_header\n";
  const double p[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 0.1 + 1e-12}};
  for (int v = 0; v < 5; ++v) {
    for (double x : p[v]) put_big(s, x);
    for (int k = 0; k < 3; ++k) put_big(s, 0.5f);
    for (unsigned char c : {(unsigned char)(v * 50), (unsigned char)255, (unsigned char)0, (unsigned char)7}) s.push_back(char(c));
  }
  s.push_back(3), put_big(s, 0), put_big(s, 2), put_big(s, 1);
  s.push_back(4), put_big(s, 0), put_big(s, 1), put_big(s, 4), put_big(s, 3);
  return s;
}

}  // namespace

TEST_CASE("Binary PLY: big-endian doubles, colours, polygons; a short file is left to the checked reader", "[read_binary_ply]") {
  BinaryPly ply;
  REQUIRE(read_binary_ply(big_endian_ply(2), ply));
  REQUIRE(ply.points.size() == 5);
  CHECK(ply.points[4].z() == 0.1 + 1e-12);  // double precision kept
  CHECK(ply.points[2] == Eigen::Vector3d(1, 1, 0));
  REQUIRE(ply.colors.size() == 5);
  CHECK(ply.colors[2].x() == Approx(100 / 255.0));
  CHECK(ply.colors[2].y() == 1.0f);
  CHECK(ply.triangles.empty());  // a quad: every face as a polygon
  REQUIRE(ply.polygons.size() == 2);
  CHECK(ply.polygons[0] == std::vector<int>{0, 2, 1});
  CHECK(ply.polygons[1] == std::vector<int>{0, 1, 4, 3});
  BinaryPly short_file;
  CHECK_FALSE(read_binary_ply(big_endian_ply(3), short_file));  // a third face announced, not there
}

TEST_CASE("Binary PLY: anything unusual is left to the checked reader", "[read_binary_ply]") {
  const std::string head = "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n";
  const std::string faces = "element face 0\nproperty list uchar int vertex_indices\n";
  BinaryPly ply;
  CHECK(read_binary_ply(head + faces + "end_header\n", ply));
  // ASCII of the same shape is read here too; an ASCII line with a value too many is left to the checks.
  const std::string ascii = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n" +
                            std::string("element face 0\nproperty list uint ushort vertex_indices\nend_header\n");
  CHECK(read_binary_ply(ascii + "1 2 3\n", ply));
  CHECK(ply.points.size() == 1);
  CHECK(ply.points[0] == Eigen::Vector3d(1, 2, 3));
  CHECK_FALSE(read_binary_ply(ascii + "1 2 3 4\n", ply));
  CHECK_FALSE(read_binary_ply(ascii + "1 2 nan\n", ply));
  CHECK_FALSE(read_binary_ply(head + faces + "property list uchar float texcoord\nend_header\n", ply));  // face uv
  CHECK_FALSE(read_binary_ply(head + faces + "element edge 0\nproperty int vertex1\nend_header\n", ply));
  CHECK_FALSE(read_binary_ply(head + "property ushort red\nproperty ushort green\nproperty ushort blue\n" + faces + "end_header\n", ply));
  CHECK_FALSE(read_binary_ply("ply\ncomment TextureFile t.png\n" + head.substr(4) + faces + "end_header\n", ply));
  CHECK_FALSE(read_binary_ply(head + faces, ply));  // no end_header
  // A corner out of range goes to the checked path, which reports it.
  std::string one = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n" +
                    faces.substr(0, 13) + "1\nproperty list uchar int vertex_indices\nend_header\n";
  one.append(12, '\0');
  one.push_back(3);
  for (int i : {0, 0, 5}) one.append(reinterpret_cast<const char*>(&i), 4);
  CHECK_FALSE(read_binary_ply(one, ply));
}

TEST_CASE("A mesh written as binary PLY reads back through the fast reader as written", "[read_binary_ply]") {
  test_util::TempDir dir;
  const sdm::Mesh m = sdm::make_primitive("bottle");
  sdm::write_mesh(m, dir / "m.ply");
  std::ifstream in(dir / "m.ply", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  BinaryPly ply;
  REQUIRE(read_binary_ply(bytes, ply));
  const sdm::MeshSoup soup = sdm::read_mesh_soup(dir / "m.ply");
  REQUIRE(soup.points.size() == m.n_vertices());
  REQUIRE(soup.triangles == ply.triangles);
  // Exactly the written coordinates (the writer keeps doubles where float would change one), and
  // what OpenMesh's own PLY reader reads from it to within its single-precision path.
  sdm::Mesh reference;
  REQUIRE(OpenMesh::IO::read_mesh(reference, dir / "m.ply"));
  REQUIRE(reference.n_vertices() == m.n_vertices());
  for (auto v : m.vertices()) CHECK(soup.points[size_t(v.idx())] == sdm::point(m, v));
  for (auto v : reference.vertices()) CHECK((soup.points[size_t(v.idx())] - sdm::point(reference, v)).norm() < 1e-6);
  for (auto fh : m.faces()) {
    int c = 0;
    for (auto v : m.fv_range(fh)) CHECK(soup.triangles[size_t(fh.idx())][c++] == v.idx());
  }
  // Colours written by write_colored_ply come back.
  std::vector<Eigen::Vector3f> colors(m.n_vertices());
  for (size_t i = 0; i < colors.size(); ++i) colors[i] = Eigen::Vector3f(float(i % 256) / 255.f, 0.5f, 1.0f);
  sdm::write_colored_ply(m, colors, dir / "c.ply");
  const sdm::MeshSoup colored = sdm::read_mesh_soup(dir / "c.ply");
  REQUIRE(colored.colors.size() == m.n_vertices());
  for (size_t i = 0; i < colors.size(); ++i) CHECK((colored.colors[i] - colors[i]).norm() < 0.6f / 255.f);
  // A truncated file keeps the checked path's message.
  std::ofstream(dir / "t.ply", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  CHECK_THROWS_AS(sdm::read_mesh_soup(dir / "t.ply"), sdm::InputError);
}
