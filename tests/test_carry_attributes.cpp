// Per-vertex attributes carried through a correspondence (carry_attributes): a colour that encodes
// the source's position, carried onto a remesh of the source, decodes to the target vertex's own
// position; texture sampling follows the renderer's conventions; PLY vertex colours round-trip
// through write_colored_ply and load_mesh.
#include "libstm/mesh/load_mesh.h"
#include "libstm/transfer/carry_attributes.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/mesh/primitives.h"
#include "libstm/core/errors.h"
#include "synthetic_shapes.h"
#include "test_util.h"

#include <catch2/catch.hpp>

#include <fstream>

namespace {

// Position -> colour in [0, 1]^3 over the box [lo, hi], and back.
struct PositionCode {
  Eigen::Vector3d lo, hi;
  Eigen::Vector3f encode(const Eigen::Vector3d& p) const { return ((p - lo).cwiseQuotient(hi - lo)).cast<float>(); }
  Eigen::Vector3d decode(const Eigen::Vector3f& c) const { return lo + c.cast<double>().cwiseProduct(hi - lo); }
};

std::vector<Eigen::Vector3d> points_of(const sdm::Mesh& m) {
  std::vector<Eigen::Vector3d> p;
  for (auto v : m.vertices()) p.push_back(sdm::point(m, v));
  return p;
}

}  // namespace

// The source's colour encodes its position; the target is the source tessellated anew (vertices
// projected onto the source's surface), its correspondence the closest source points. The blend of
// the corner colours is linear in position, so every target vertex decodes to its source point,
// which lies on the target vertex up to the projection's rounding: the tolerance is a thousandth of
// the source's mean edge.
TEST_CASE("colours encoding the position carried onto a remesh decode to the target's positions", "[carry_attributes]") {
  const sdm::Mesh a = sdm::make_primitive("ypsilon", 2000);
  const sdm::Mesh b = synth::remeshed(a, 0.75);
  REQUIRE(b.n_vertices() != a.n_vertices());
  PositionCode code;
  sdm::bounding_box(a, code.lo, code.hi);
  std::vector<Eigen::Vector3f> colors;
  for (auto v : a.vertices()) colors.push_back(code.encode(sdm::point(a, v)));
  const std::vector<sdm::SourcePoint> corr = sdm::source_points_under(a, points_of(a), points_of(b));
  const std::vector<Eigen::Vector3f> carried = sdm::carry_vertex_colors(a, colors, corr);
  REQUIRE(carried.size() == b.n_vertices());
  const double edge = synth::mean_edge(a);
  double worst = 0;
  for (auto v : b.vertices()) worst = std::max(worst, (code.decode(carried[v.idx()]) - sdm::point(b, v)).norm());
  WARN("ypsilon onto its remesh (" << b.n_vertices() << " vertices): largest decoded position error " << worst / edge
                                   << " mean edges");
  CHECK(worst < 1e-3 * edge);

  // A correspondence made for another source is refused, as is a colour list of the wrong size.
  std::vector<sdm::SourcePoint> bad = corr;
  bad[3].face = int(a.n_faces());
  CHECK_THROWS_AS(sdm::carry_vertex_colors(a, colors, bad), sdm::InputError);
  colors.pop_back();
  CHECK_THROWS_AS(sdm::carry_vertex_colors(a, colors, corr), sdm::InputError);
}

// The same through the texture: the source's uv are its planar projection onto x, y, scaled into
// [0.1, 0.9], and the texture holds u and v in red and green (linear ramps, exact between texel
// centres), so the colour at a target vertex's source point gives back its projected position to
// the 8-bit steps of the ramps.
TEST_CASE("texture colours carried onto a remesh give back the target's projected position", "[carry_attributes]") {
  sdm::Mesh a = sdm::make_primitive("ypsilon", 2000);
  const sdm::Mesh b = synth::remeshed(a, 0.75);
  Eigen::Vector3d lo, hi;
  sdm::bounding_box(a, lo, hi);
  a.request_halfedge_texcoords2D();
  for (auto h : a.halfedges()) {
    if (a.is_boundary(h)) continue;
    const Eigen::Vector3d p = sdm::point(a, a.to_vertex_handle(h));
    a.set_texcoord2D(h, sdm::Mesh::TexCoord2D(0.1 + 0.8 * (p.x() - lo.x()) / (hi.x() - lo.x()), 0.1 + 0.8 * (p.y() - lo.y()) / (hi.y() - lo.y())));
  }
  const int n = 256;
  sdm::Image tex(n, n, 4, 255);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      tex.at(x, y)[0] = uint8_t(std::lround(255.0 * (x + 0.5) / n));
      tex.at(x, y)[1] = uint8_t(std::lround(255.0 * (n - y - 0.5) / n));  // rows top to bottom, v bottom to top
      tex.at(x, y)[2] = 0;
    }
  const std::vector<sdm::SourcePoint> corr = sdm::source_points_under(a, points_of(a), points_of(b));
  const std::vector<Eigen::Vector3f> carried = sdm::carry_texture_colors(a, tex, corr);
  REQUIRE(carried.size() == b.n_vertices());
  double worst = 0;
  for (auto v : b.vertices()) {
    const Eigen::Vector3d p = sdm::point(b, v);
    const Eigen::Vector2d uv(0.1 + 0.8 * (p.x() - lo.x()) / (hi.x() - lo.x()), 0.1 + 0.8 * (p.y() - lo.y()) / (hi.y() - lo.y()));
    worst = std::max(worst, (carried[v.idx()].head<2>().cast<double>() - uv).cwiseAbs().maxCoeff());
  }
  WARN("texture colours carried onto the remesh: largest error in u or v " << 255 * worst << " / 255 (8-bit steps of the ramps)");
  CHECK(worst < 0.5 / 255 + 1e-6);
  a.release_halfedge_texcoords2D();
  CHECK_THROWS_AS(sdm::carry_texture_colors(a, tex, corr), sdm::InputError);
}

TEST_CASE("sample_texture: texel centres exactly, bilinear between them, uv origin bottom left, repeating", "[carry_attributes]") {
  sdm::Image t(2, 2, 4, 255);
  const uint8_t rgb[4][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 255}};  // top left, top right, bottom left, bottom right
  for (int k = 0; k < 4; ++k)
    for (int c = 0; c < 3; ++c) t.at(k % 2, k / 2)[c] = rgb[k][c];
  auto near = [](const Eigen::Vector3f& a, const Eigen::Vector3f& b) { return (a - b).cwiseAbs().maxCoeff() < 1e-6f; };
  CHECK(near(sdm::sample_texture(t, {0.25, 0.75}), Eigen::Vector3f(1, 0, 0)));  // top left
  CHECK(near(sdm::sample_texture(t, {0.25, 0.25}), Eigen::Vector3f(0, 0, 1)));  // bottom left
  CHECK(near(sdm::sample_texture(t, {0.75, 0.25}), Eigen::Vector3f(1, 1, 1)));  // bottom right
  CHECK(near(sdm::sample_texture(t, {0.5, 0.75}), Eigen::Vector3f(0.5f, 0.5f, 0)));
  CHECK(near(sdm::sample_texture(t, {0.5, 0.5}), Eigen::Vector3f(0.5f, 0.5f, 0.5f)));
  CHECK(near(sdm::sample_texture(t, {1.25, -0.25}), sdm::sample_texture(t, {0.25, 0.75})));
  CHECK(near(sdm::sample_texture(t, {0.0, 0.75}), Eigen::Vector3f(0.5f, 0.5f, 0)));  // the left edge blends with the right column
}

TEST_CASE("PLY vertex colours round-trip through write_colored_ply and load_mesh", "[carry_attributes]") {
  test_util::TempDir dir;
  const sdm::Mesh m = sdm::make_primitive("donut");
  std::vector<Eigen::Vector3f> colors;
  for (auto v : m.vertices()) colors.push_back(Eigen::Vector3f(float(v.idx() % 256), float((7 * v.idx()) % 256), 255.f) / 255.f);
  sdm::write_colored_ply(m, colors, dir / "donut.ply");
  std::ifstream in(dir / "donut.ply", std::ios::binary);
  std::string header((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  header = header.substr(0, header.find("end_header"));
  CHECK(header.find("binary_little_endian") != std::string::npos);
  for (const char* p : {"property uchar red", "property uchar green", "property uchar blue"}) CHECK(header.find(p) != std::string::npos);
  std::vector<Eigen::Vector3f> back;
  sdm::LoadedMesh r_read = sdm::load_mesh(dir / "donut.ply");
  back = std::move(r_read.colors);
  const sdm::Mesh r = std::move(r_read.mesh);
  REQUIRE(r.n_vertices() == m.n_vertices());
  REQUIRE(back.size() == colors.size());
  float worst = 0;
  for (size_t i = 0; i < back.size(); ++i) worst = std::max(worst, (back[i] - colors[i]).cwiseAbs().maxCoeff());
  CHECK(worst < 1e-6f);
  // ASCII PLY (a tetrahedron) with colours between the coordinates and other properties.
  test_util::write_file(dir / "tet.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                                         "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
                                         "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
                                         "0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n0 0 1 51 102 153 255\n"
                                         "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  sdm::LoadedMesh tet_read = sdm::load_mesh(dir / "tet.ply");
  back = std::move(tet_read.colors);
  const sdm::Mesh tet = std::move(tet_read.mesh);
  REQUIRE(back.size() == 4);
  CHECK((back[0] - Eigen::Vector3f(1, 0, 0)).norm() < 1e-6f);
  CHECK((back[3] - Eigen::Vector3f(0.2f, 0.4f, 0.6f)).norm() < 1e-6f);
  CHECK((sdm::point(tet, tet.vertex_handle(3)) - Eigen::Vector3d(0, 0, 1)).norm() < 1e-12);
  // Without colours, none are reported; a wrong extension or count is refused and writes nothing.
  sdm::write_mesh(m, dir / "plain.ply");
  back = sdm::load_mesh(dir / "plain.ply").colors;
  CHECK(back.empty());
  CHECK_THROWS_AS(sdm::write_colored_ply(m, colors, dir / "donut.obj"), sdm::InputError);
  colors.pop_back();
  CHECK_THROWS_AS(sdm::write_colored_ply(m, colors, dir / "short.ply"), sdm::InputError);
  CHECK(!std::filesystem::exists(dir / "donut.obj"));
  CHECK(!std::filesystem::exists(dir / "short.ply"));
}
