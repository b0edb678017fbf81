// Mesh repair (libstm/mesh/repair_soup.h): each defect class built on a mesh whose answer is known,
// the repaired result checked face by face against it.
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/primitives.h"
#include "libstm/mesh/repair_soup.h"
#include "libstm/mesh/validate_mesh.h"
#include "test_util.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <fstream>
#include <map>
#include <set>

namespace {

sdm::MeshSoup capsule_soup(int resolution = 400) { return sdm::mesh_to_soup(sdm::make_primitive("capsule", resolution)); }

// `mesh` as a soup: every triangle with its own three points.
sdm::MeshSoup unwelded(const sdm::MeshSoup& mesh) {
  sdm::MeshSoup s;
  for (const auto& t : mesh.triangles) {
    const int n = int(s.points.size());
    for (int v : t) s.points.push_back(mesh.points[size_t(v)]);
    s.triangles.push_back({n, n + 1, n + 2});
  }
  return s;
}

// The three points of triangle t of `s`, starting at its smallest point (lexicographic), so that
// two triangles over the same points in the same orientation compare equal.
std::array<Eigen::Vector3d, 3> corners(const sdm::MeshSoup& s, const std::array<int, 3>& t) {
  std::array<Eigen::Vector3d, 3> c = {s.points[size_t(t[0])], s.points[size_t(t[1])], s.points[size_t(t[2])]};
  auto less = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3); };
  const size_t first = size_t(std::min_element(c.begin(), c.end(), less) - c.begin());
  std::rotate(c.begin(), c.begin() + long(first), c.end());
  return c;
}

// Every output triangle shows the points of the input triangle it comes from, in the same
// orientation (or the opposite, where `flipped` says so).
void require_same_faces(const sdm::MeshSoup& in, const sdm::MeshSoup& out, const sdm::RepairReport& r,
                        const std::set<int>& flipped = {}) {
  REQUIRE(r.face_source.size() == out.triangles.size());
  for (size_t f = 0; f < out.triangles.size(); ++f) {
    const int g = r.face_source[f];
    auto want = in.triangles[size_t(g)];
    if (flipped.count(g)) std::swap(want[1], want[2]);
    INFO("output face " << f << " from input face " << g);
    REQUIRE(corners(out, out.triangles[f]) == corners(in, want));
  }
}

// The validation facts a closed, consistently oriented 2-manifold has.
void require_closed_manifold(const sdm::MeshSoup& soup, int parts) {
  const sdm::MeshReport v = sdm::validate_mesh(soup);
  INFO(v.to_json().dump());
  REQUIRE(v.usable());
  REQUIRE(v.parts == parts);
  REQUIRE(v.boundary_loops == 0);
  for (int g : v.genus_per_part) REQUIRE(g == 0);
}

// A copy of `s` point-reflected through the midpoint of edge (p, q) and turned the right way out,
// appended to `s` with its own points except p and q, which it shares: the two convex bodies
// then touch along that edge only, which four faces use.
void add_reflected_through_edge(sdm::MeshSoup& s, int p, int q) {
  const Eigen::Vector3d m = 0.5 * (s.points[size_t(p)] + s.points[size_t(q)]);
  const int n = int(s.points.size()), nf = int(s.triangles.size());
  std::vector<int> index(static_cast<size_t>(n), 0);
  for (int v = 0; v < n; ++v) {
    index[size_t(v)] = v == p ? q : v == q ? p : int(s.points.size());
    if (v != p && v != q) s.points.push_back(2 * m - s.points[size_t(v)]);
  }
  for (int f = 0; f < nf; ++f) {
    const auto t = s.triangles[size_t(f)];
    s.triangles.push_back({index[size_t(t[0])], index[size_t(t[2])], index[size_t(t[1])]});
  }
}

}  // namespace

TEST_CASE("repair leaves a clean closed mesh as it is", "[repair_soup]") {
  sdm::MeshSoup s = capsule_soup();
  const sdm::MeshSoup in = s;
  const sdm::RepairReport r = sdm::repair_soup(s);
  REQUIRE_FALSE(r.changed());
  REQUIRE(s.triangles == in.triangles);
  REQUIRE(s.points == in.points);
}

TEST_CASE("repair: a pinched vertex is split into one copy per fan", "[repair_soup]") {
  // Two capsules, the second moved so that its lowest vertex lands exactly on the first's highest,
  // and made to share it: one vertex where two fans meet.
  sdm::MeshSoup s = capsule_soup();
  const int n = int(s.points.size()), nf = int(s.triangles.size());
  int top = 0, bottom = 0;
  for (int v = 0; v < n; ++v) {
    if (s.points[size_t(v)].z() > s.points[size_t(top)].z()) top = v;
    if (s.points[size_t(v)].z() < s.points[size_t(bottom)].z()) bottom = v;
  }
  const Eigen::Vector3d shift = s.points[size_t(top)] - s.points[size_t(bottom)];
  for (int v = 0; v < n; ++v) s.points.push_back(s.points[size_t(v)] + shift);
  for (int f = 0; f < nf; ++f) {
    auto t = s.triangles[size_t(f)];
    for (int& v : t) v = v == bottom ? top : v + n;
    s.triangles.push_back(t);
  }
  REQUIRE_FALSE(sdm::validate_mesh(s).usable());
  const sdm::MeshSoup in = s;
  const sdm::RepairReport r = sdm::repair_soup(s);
  REQUIRE(r.count("non-manifold vertices split (one copy per fan of faces)") == 1);
  REQUIRE(r.faces_dropped() == 0);
  require_same_faces(in, s, r);
  require_closed_manifold(s, 2);
  // One vertex more than the two capsules' own, minus the shared one: 2 n - 1 + 1 - 1 unused.
  REQUIRE(s.points.size() == size_t(2 * n));
}

TEST_CASE("repair: a duplicated face is dropped, the first kept", "[repair_soup]") {
  sdm::MeshSoup s = capsule_soup();
  const size_t nf = s.triangles.size();
  auto copy = s.triangles[17];
  std::rotate(copy.begin(), copy.begin() + 1, copy.end());  // the same face, written from another corner
  s.triangles.push_back(copy);
  const sdm::MeshSoup in = s;
  const sdm::RepairReport r = sdm::repair_soup(s);
  REQUIRE(r.count("faces dropped: duplicates of another face") == 1);
  REQUIRE(s.triangles.size() == nf);
  for (size_t f = 0; f < nf; ++f) REQUIRE(r.face_source[f] == int(f));  // the copy, last, is the one dropped
  require_same_faces(in, s, r);
  require_closed_manifold(s, 1);
}

TEST_CASE("repair: a face the wrong way round is turned back", "[repair_soup]") {
  sdm::MeshSoup s = capsule_soup();
  std::swap(s.triangles[40][1], s.triangles[40][2]);
  REQUIRE_FALSE(sdm::validate_mesh(s).usable());
  const sdm::MeshSoup in = s;
  const sdm::RepairReport r = sdm::repair_soup(s);
  REQUIRE(r.count("faces flipped to agree with the rest of their part") == 1);
  require_same_faces(in, s, r, {40});
  require_closed_manifold(s, 1);
}

TEST_CASE("repair: a non-manifold edge joining two closed bodies splits them apart", "[repair_soup]") {
  sdm::MeshSoup s = capsule_soup();
  const auto t = s.triangles[5];
  add_reflected_through_edge(s, t[0], t[1]);
  const sdm::MeshReport before = sdm::validate_mesh(s);
  REQUIRE_FALSE(before.usable());
  const sdm::MeshSoup in = s;
  const sdm::RepairReport r = sdm::repair_soup(s);
  REQUIRE(r.count("non-manifold edges split (faces paired around the edge, the rest peeled off as a sheet)") == 1);
  REQUIRE(r.faces_dropped() == 0);
  require_same_faces(in, s, r);
  require_closed_manifold(s, 2);
  // Each body got its own copy of the edge's two vertices.
  REQUIRE(s.points.size() == in.points.size() + 2);
}

TEST_CASE("repair: a triangle soup welds back into the mesh it was", "[repair_soup]") {
  const sdm::MeshSoup mesh = capsule_soup();
  sdm::MeshSoup s = unwelded(mesh);
  const sdm::MeshSoup in = s;
  const sdm::RepairReport r = sdm::repair_soup(s);
  REQUIRE(r.count("coincident vertices welded (exact)") == long(in.points.size() - mesh.points.size()));
  REQUIRE(s.points.size() == mesh.points.size());
  require_same_faces(in, s, r);
  require_closed_manifold(s, 1);
}

TEST_CASE("repair: a crack narrower than the tolerance welds, a wider one stays open", "[repair_soup]") {
  sdm::MeshSoup s = capsule_soup();
  const sdm::MeshSoup in = s;
  // Every face above the ring of vertices nearest z = 0 gets its own copies of the ring's
  // vertices, moved by 4e-8 (under a millionth of the diagonal, 4.9).
  std::map<double, int> rings;
  for (const auto& p : s.points) rings[p.z()]++;
  double z0 = 1e9;
  for (const auto& [z, count] : rings)
    if (count >= 8 && std::abs(z) < std::abs(z0)) z0 = z;
  std::map<int, int> copy;
  for (auto& t : s.triangles) {
    const double zc = (s.points[size_t(t[0])].z() + s.points[size_t(t[1])].z() + s.points[size_t(t[2])].z()) / 3;
    if (zc <= z0) continue;
    for (int& v : t)
      if (s.points[size_t(v)].z() == z0) {
        if (!copy.count(v)) copy[v] = int(s.points.size()), s.points.push_back(s.points[size_t(v)] + Eigen::Vector3d(4e-8, 0, 0));
        v = copy[v];
      }
  }
  REQUIRE(!copy.empty());
  sdm::MeshSoup wide = s;
  REQUIRE(sdm::validate_mesh(s).boundary_loops == 2);
  const sdm::RepairReport r = sdm::repair_soup(s);
  REQUIRE(r.weld_distance > 4e-8);
  REQUIRE(r.count("coincident vertices welded (exact)") == 0);
  require_closed_manifold(s, 1);
  const sdm::RepairReport exact = sdm::repair_soup(wide, {0.0});
  REQUIRE(sdm::validate_mesh(wide).boundary_loops == 2);
  REQUIRE_FALSE(exact.changed());
}

TEST_CASE("one soup through OBJ, STL, PLY and glTF loads as one mesh", "[repair_soup][load_mesh]") {
  test_util::TempDir dir;
  const sdm::MeshSoup mesh = capsule_soup();
  sdm::Mesh soup;  // every triangle with its own three vertices: a halfedge mesh can hold that
  for (const auto& t : mesh.triangles) {
    std::vector<sdm::Mesh::VertexHandle> h;
    for (int v : t) h.push_back(soup.add_vertex(sdm::Mesh::Point(mesh.points[size_t(v)].data())));
    soup.add_face(h);
  }
  std::vector<std::set<std::array<double, 9>>> faces;
  for (const std::string ext : {".obj", ".stl", ".ply", ".glb"}) {
    const std::string path = dir / ("soup" + ext);
    sdm::write_mesh(soup, path);
    const sdm::LoadedMesh m = sdm::load_mesh(path, sdm::LoadOptions{});
    INFO(ext);
    REQUIRE(m.mesh.n_vertices() == mesh.points.size());
    REQUIRE(m.mesh.n_faces() == mesh.triangles.size());
    const sdm::MeshSoup back = sdm::mesh_to_soup(m.mesh);
    std::set<std::array<double, 9>> set;
    for (const auto& t : back.triangles) {
      const auto c = corners(back, t);
      set.insert({c[0].x(), c[0].y(), c[0].z(), c[1].x(), c[1].y(), c[1].z(), c[2].x(), c[2].y(), c[2].z()});
    }
    faces.push_back(set);
  }
  // STL and glTF store floats: compare against the float-rounded OBJ/PLY answer.
  for (auto& set : faces) {
    std::set<std::array<double, 9>> rounded;
    for (auto a : set) {
      for (double& x : a) x = double(float(x));
      rounded.insert(a);
    }
    set = rounded;
  }
  for (size_t i = 1; i < faces.size(); ++i) REQUIRE(faces[i] == faces[0]);
}

TEST_CASE("an OBJ that starts with a byte-order mark keeps its first vertex", "[repair_soup][load_mesh]") {
  test_util::TempDir dir;
  const std::string cube =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
      "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
  for (const std::string extra : {"", "vt 0 0\nvt 1 0\nvt 1 1\n"}) {  // the fast reader's path, then OpenMesh's
    const std::string path = dir / "bom.obj";
    std::ofstream(path, std::ios::binary) << "\xEF\xBB\xBF" << cube << extra;
    const sdm::MeshSoup s = sdm::read_mesh_soup(path);
    INFO(extra);
    REQUIRE(s.points.size() == 8);
    REQUIRE(s.points[0] == Eigen::Vector3d(0, 0, 0));
    require_closed_manifold(s, 1);
  }
}

namespace {

// A bipyramid of `n` sides and radius 1 about the z axis, its lower apex at `at`, its upper one
// 2 h above; `top`, when given, an existing point there, shared with the body it belongs to.
void add_bipyramid(sdm::MeshSoup& s, int n, double h, const Eigen::Vector3d& at, int top = -1) {
  const int apex = int(s.points.size());
  s.points.push_back(at);
  if (top < 0) top = int(s.points.size()), s.points.push_back(at + Eigen::Vector3d(0, 0, 2 * h));
  const int ring = int(s.points.size());
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    s.points.push_back(at + Eigen::Vector3d(std::cos(a), std::sin(a), h));
  }
  for (int i = 0; i < n; ++i) {
    const int p = ring + i, q = ring + (i + 1) % n;
    s.triangles.push_back({apex, q, p});
    s.triangles.push_back({top, p, q});
  }
}

// Every field repair_soup writes, equal between the repair with hints and the one without.
void require_same_repair(const sdm::MeshSoup& in) {
  sdm::MeshSoup full = in, hinted = in;
  const sdm::RepairReport a = sdm::repair_soup(full);
  const sdm::TopologyScan scan = sdm::scan_topology(in);
  const sdm::RepairReport b = sdm::repair_soup(hinted, {}, sdm::repair_hints(scan));
  REQUIRE(a.steps.size() == b.steps.size());
  for (size_t i = 0; i < a.steps.size(); ++i) {
    INFO(a.steps[i].kind);
    REQUIRE(a.steps[i].kind == b.steps[i].kind);
    REQUIRE(a.steps[i].count == b.steps[i].count);
    REQUIRE(a.steps[i].example == b.steps[i].example);
  }
  REQUIRE(a.face_source == b.face_source);
  REQUIRE(a.point_source == b.point_source);
  REQUIRE(full.triangles == hinted.triangles);
  REQUIRE(full.points == hinted.points);
}

}  // namespace

TEST_CASE("validation counts the fans of vertices in few faces and in many alike", "[repair_soup][validate]") {
  // Bipyramids hanging from one point, vertex 0 (the first one's lower apex): a fan of n faces
  // each there (n = 8: 16 or 24 faces, a walk over bit sets; n = 24: 48 or 72, the sorted path).
  for (int n : {8, 24}) {
    for (int bodies : {2, 3}) {
      sdm::MeshSoup s;
      add_bipyramid(s, n, 1.0, Eigen::Vector3d::Zero());
      for (int b = 1; b < bodies; ++b) add_bipyramid(s, n, 1.0 + b, Eigen::Vector3d(0, 0, -2.0 * (1.0 + b)), 0);
      INFO("n " << n << ", bodies " << bodies);
      const sdm::TopologyScan scan = sdm::scan_topology(s);
      REQUIRE(scan.nonmanifold_vertices == std::vector<int>{0});
      const sdm::MeshReport r = sdm::validate_mesh(s);
      REQUIRE_THAT(r.to_json().dump(), Catch::Contains("vertex 0 where " + std::to_string(bodies) + " fans of faces meet"));
      require_same_repair(s);
      sdm::MeshSoup fixed = s;
      sdm::repair_soup(fixed, {}, sdm::repair_hints(scan));
      require_closed_manifold(fixed, bodies);
    }
  }
}

TEST_CASE("repair from validation's scan does what the full repair does", "[repair_soup]") {
  SECTION("a pinched vertex, a duplicate and a flipped face together") {
    sdm::MeshSoup s = capsule_soup();
    add_bipyramid(s, 6, 0.2, s.points[0] - Eigen::Vector3d(0, 0, 0.4), 0);  // hangs from the capsule's vertex 0
    s.triangles.push_back(s.triangles[30]);
    std::swap(s.triangles[50][1], s.triangles[50][2]);
    require_same_repair(s);
  }
  SECTION("a non-manifold edge") {
    sdm::MeshSoup s = capsule_soup();
    const auto t = s.triangles[5];
    add_reflected_through_edge(s, t[0], t[1]);
    require_same_repair(s);
  }
  SECTION("a soup") {
    require_same_repair(unwelded(capsule_soup()));
  }
}

TEST_CASE("a face and its reverse back to back beside a pinched mesh are dropped too", "[repair_soup][load_mesh]") {
  // The scan sees the pinched vertex and repairs at once; the pair, whose edges are each used twice
  // in opposite directions, only shows to the full validation after it, and is repaired then.
  sdm::MeshSoup s = capsule_soup();
  const size_t capsule_faces = s.triangles.size();
  add_bipyramid(s, 6, 0.2, s.points[0] - Eigen::Vector3d(0, 0, 0.4), 0);
  const size_t bodies = s.triangles.size();
  const int n = int(s.points.size());
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(5, 0, 0), Eigen::Vector3d(5.01, 0, 0), Eigen::Vector3d(5, 0.01, 0)}) s.points.push_back(p);
  s.triangles.push_back({n, n + 1, n + 2});
  s.triangles.push_back({n, n + 2, n + 1});
  const sdm::LoadReport r = sdm::repair_and_validate(s, sdm::LoadOptions{});
  INFO(r.validation.to_json().dump());
  REQUIRE(r.validation.usable());
  REQUIRE(r.repair.count("non-manifold vertices split (one copy per fan of faces)") == 1);
  REQUIRE(r.repair.count("faces dropped: duplicates of another face") == 1);
  REQUIRE(s.triangles.size() == bodies);  // the lone triangle left of the pair went as a flat fragment
  REQUIRE(r.validation.parts == 2);
  REQUIRE(r.repair.face_source.size() == s.triangles.size());
  for (size_t f = 0; f < capsule_faces; ++f) REQUIRE(r.repair.face_source[f] == int(f));
}

TEST_CASE("the edge table without some faces equals the table made anew", "[repair_soup]") {
  sdm::MeshSoup s = capsule_soup(200);
  std::vector<char> keep(s.triangles.size(), 1);
  for (size_t f = 0; f < keep.size(); f += 7) keep[f] = 0;
  std::vector<int> index(keep.size(), -1);
  sdm::MeshSoup fewer = s;
  fewer.triangles.clear();
  for (size_t f = 0; f < keep.size(); ++f)
    if (keep[f]) index[f] = int(fewer.triangles.size()), fewer.triangles.push_back(s.triangles[f]);
  const sdm::EdgeTable a = sdm::without_faces(sdm::edge_table(s), index), b = sdm::edge_table(fewer);
  REQUIRE(a.lo == b.lo);
  REQUIRE(a.hi == b.hi);
  REQUIRE(a.halfedge == b.halfedge);
  REQUIRE(a.forward == b.forward);
  REQUIRE(a.group == b.group);
}
