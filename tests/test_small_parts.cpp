// Small separate parts (libstm/correspondence/small_parts, DECISIONS 5, "Small separate parts"): a closed blob
// of six vertices inside a model, as inside a scanned body's pelvis, is left out of the matching
// (its skeleton would get a part of its own and the pair be refused as "connected parts 1 vs 2"),
// and its vertices take the nearest vertex's source point; `--strict` keeps the refusal.
#include "libstm/correspondence/small_parts.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "correspondence_points.h"
#include "synthetic_shapes.h"
#include "test_util.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

namespace {

// `mesh` with a closed octahedron of radius `r` (six vertices, eight faces, facing out) at `centre`
// appended: its vertices and faces come last.
sdm::Mesh with_blob(const sdm::Mesh& mesh, const Eigen::Vector3d& centre, double r) {
  sdm::MeshSoup soup = sdm::mesh_to_soup(mesh);
  const int o = int(soup.points.size());
  const Eigen::Vector3d d[6] = {{r, 0, 0}, {-r, 0, 0}, {0, r, 0}, {0, -r, 0}, {0, 0, r}, {0, 0, -r}};
  for (const auto& x : d) soup.points.push_back(centre + x);
  const int t[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (const auto& f : t) soup.triangles.push_back({o + f[0], o + f[1], o + f[2]});
  return sdm::build_mesh(soup);
}

// The vertex of `mesh` nearest p.
Eigen::Vector3d nearest_vertex(const sdm::Mesh& mesh, const Eigen::Vector3d& p) {
  Eigen::Vector3d best = sdm::point(mesh, *mesh.vertices().begin());
  for (auto v : mesh.vertices())
    if ((sdm::point(mesh, v) - p).norm() < (best - p).norm()) best = sdm::point(mesh, v);
  return best;
}

}  // namespace

TEST_CASE("without_small_parts leaves out a blob inside a model and the correspondence covers it again", "[small_parts]") {
  const sdm::Mesh y = sdm::make_primitive("ypsilon", 1200);
  const sdm::Mesh m = with_blob(y, Eigen::Vector3d::Zero(), 0.05);
  REQUIRE(m.n_vertices() == y.n_vertices() + 6);
  const sdm::MainParts p = sdm::without_small_parts(m);
  REQUIRE(p.left_out.size() == 1);
  CHECK(p.left_out[0].find("6 vertices") != std::string::npos);
  CHECK(p.mesh.n_vertices() == y.n_vertices());
  CHECK(p.mesh.n_faces() == y.n_faces());
  for (size_t i = 0; i < p.vertex_of.size(); ++i) CHECK(p.vertex_of[i] == int(i));  // the blob came last
  CHECK(sdm::surface_area(p.mesh) == Approx(sdm::surface_area(y)).epsilon(1e-12));
  // The main part alone is left whole.
  CHECK(!sdm::without_small_parts(y).reduced());
  // Per main vertex its own position as a source point (a face around it, weight 1 at it); the
  // blob's vertices take their nearest main vertex's, all within the tube's radius of the junction.
  std::vector<sdm::SourcePoint> c;
  for (auto v : p.mesh.vertices()) {
    const auto h = p.mesh.halfedge_handle(v);
    const auto f = p.mesh.face_handle(h).is_valid() ? p.mesh.face_handle(h) : p.mesh.opposite_face_handle(h);
    sdm::SourcePoint s;
    s.face = f.idx();
    int k = 0;
    for (auto x : p.mesh.fv_range(f)) s.barycentric[k++] = x == v ? 1.0 : 0.0;
    c.push_back(s);
  }
  const std::vector<sdm::SourcePoint> all = sdm::onto_input_target(p, m, c);
  REQUIRE(all.size() == m.n_vertices());
  for (auto v : m.vertices()) {
    const Eigen::Vector3d at = sdm::position_of(y, all[size_t(v.idx())]);
    CHECK((at - nearest_vertex(y, sdm::point(m, v))).norm() < 1e-12);
  }
}

TEST_CASE("sdm transfer leaves a blob inside either model out with a warning, and --strict refuses it", "[small_parts]") {
  test_util::TempDir dir;
  const sdm::Mesh a = sdm::make_primitive("ypsilon", 1200);
  const sdm::Mesh b = synth::remeshed(a, 0.8);
  const sdm::Mesh a_blob = with_blob(a, Eigen::Vector3d(0, -0.05, 0), 0.04), b_blob = with_blob(b, Eigen::Vector3d::Zero(), 0.05);
  sdm::write_colored_ply(a_blob, std::vector<Eigen::Vector3f>(a_blob.n_vertices(), Eigen::Vector3f(0.5f, 0.5f, 0.5f)), dir / "source.ply");
  sdm::write_mesh(b_blob, dir / "target.off");
  const std::string base = "transfer --source " + (dir / "source.ply") + " --target " + (dir / "target.off") + " -o " + (dir / "out.obj") +
                           " --size 256 --correspondence " + (dir / "c.txt");
  auto res = test_util::run_sdm(base);
  INFO(res.output);
  REQUIRE(res.exit_code == 0);
  CHECK(res.output.find("6 vertices") != std::string::npos);
  CHECK(res.output.find("left out of the matching") != std::string::npos);
  // One line per target vertex as read, onto the source as read: the same shape, so every point
  // lands near its target vertex (the blob's within the tube's radius).
  const std::vector<Eigen::Vector3d> at = test_util::read_points(dir / "c.txt", a_blob);
  REQUIRE(at.size() == b_blob.n_vertices());
  double worst = 0;
  for (auto v : b_blob.vertices())
    if (size_t(v.idx()) < b.n_vertices()) worst = std::max(worst, (at[size_t(v.idx())] - sdm::point(b_blob, v)).norm());
  // A blob vertex shows its nearest target vertex's point.
  for (size_t i = b.n_vertices(); i < at.size(); ++i)
    CHECK((at[i] - nearest_vertex(b, sdm::point(b_blob, b_blob.vertex_handle(int(i))))).norm() < 0.02 * sdm::bounding_box_diagonal(b));
  WARN("farthest source point from its target vertex: " << 100 * worst / sdm::bounding_box_diagonal(b) << " % of the diagonal");
  CHECK(worst < 0.02 * sdm::bounding_box_diagonal(b));
  std::filesystem::remove(dir / "c.txt");
  res = test_util::run_sdm(base + " --strict");
  INFO(res.output);
  CHECK(res.exit_code == 2);
  CHECK(res.output.find("refused by --strict") != std::string::npos);
  CHECK(!std::filesystem::exists(dir / "c.txt"));
}
