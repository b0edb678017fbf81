#include "libstm/core/atomic_file.h"
#include "libstm/core/errors.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/mesh/primitives.h"
#include "libstm/layout/assign_layout_faces.h"
#include "libstm/layout/atlas_triangles.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/layout/l2_stretch.h"
#include "libstm/layout/layout_json.h"
#include "libstm/layout/stm_coordinates.h"
#include "libstm/layout/segments.h"
#include "synthetic_shapes.h"
#include "test_util.h"

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sys/wait.h>
#include <unistd.h>

using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

// Atlas texels -> local (u, v) of segment g.
Vector2d atlas_to_local(const sdm::LayoutSegment& g, const Vector2d& a) {
  return g.rotated ? Vector2d(a.x() - g.x, a.y() - g.y) : Vector2d(a.y() - g.y, a.x() - g.x);
}

// Checks what every layout must satisfy on a mesh; returns the number of seam faces. `skip_span`
// names faces exempt from the half-rectangle span check (faces around a junction that lie across
// another segment's axis can span any angle).
int check_coordinates(const synth::Shape& s, const sdm::Layout& L, const std::function<bool(int)>& skip_span = {}) {
  const auto fs = sdm::assign_faces(s.mesh, s.skeleton);
  const auto tris = sdm::atlas_triangles(s.mesh, L, fs);
  std::map<int, int> copies;
  std::map<int, std::array<Vector2d, 3>> first;
  int seam = 0;
  for (const auto& t : tris) {
    const auto& g = L.segments[t.segment];
    ++copies[t.face];
    double lo = t.local[0].x(), hi = lo;
    for (int k = 0; k < 3; ++k) {
      lo = std::min(lo, t.local[k].x()), hi = std::max(hi, t.local[k].x());
      CHECK(atlas_to_local(g, t.atlas[k]).isApprox(t.local[k], 1e-12));
      CHECK(t.local[k].y() >= -1e-9);
      CHECK(t.local[k].y() <= g.w + 1e-9);
    }
    INFO("face " << t.face << " segment " << t.segment << " local " << t.local[0].transpose() << " / " << t.local[1].transpose() << " / " << t.local[2].transpose());
    if (!skip_span || !skip_span(t.face)) CHECK(hi - lo <= 0.5 * g.h);  // no triangle spans more than half its rectangle around the axis
    if (t.copy == 0) {
      first[t.face] = t.local;
      const bool inside = lo >= 0 && hi <= g.h;
      seam += !inside;
      for (int k = 0; k < 3 && inside; ++k) {
        CHECK(t.local[k].x() >= 0);
        CHECK(t.local[k].x() <= g.h);
      }
    } else {
      // The second copy of a seam triangle is the first shifted by one period.
      const double shift = t.local[0].x() - first[t.face][0].x();
      CHECK(std::abs(shift) == Approx(g.h));
      for (int k = 0; k < 3; ++k) CHECK(t.local[k].x() - first[t.face][k].x() == Approx(shift));
    }
  }
  int twice = 0;
  for (const auto& [f, n] : copies) twice += n == 2;
  CHECK(twice == seam);
  CHECK(int(copies.size()) == int(s.mesh.n_faces()));
  // Every vertex's own coordinates (canonical phi in [0, 2 pi)) lie inside its own rectangle.
  for (auto f : s.mesh.faces()) {
    const int seg = fs[f.idx()];
    const auto& g = L.segments[seg];
    for (auto v : s.mesh.fv_range(f)) {
      const auto c = sdm::capsule_uv(sdm::capsule_frame(L, seg), g.w, g.h, g.d, sdm::point(s.mesh, v));
      CHECK(c.u >= 0);
      CHECK(c.u <= g.h);
      CHECK(c.v >= 0);
      CHECK(c.v <= g.w);
    }
  }
  return seam;
}

sdm::Layout layout_of(const synth::Shape& s, int size = 1024, int margin = 4, double split_ratio = 2.0) {
  sdm::LayoutOptions o;
  o.size = size;
  o.margin = margin;
  o.split_ratio = split_ratio;
  return sdm::compute_layout(s.mesh, s.skeleton, o);
}

}  // namespace

TEST_CASE("layout: segments of a chain get their own faces, radius and cap", "[layout]") {
  const auto s = synth::capsule(0.5, 3.0, 4, 64, 10, 30);
  const auto fs = sdm::assign_faces(s.mesh, s.skeleton);
  // Faces over the cylinder part go to the segment they lie over; the caps to the end segments.
  for (auto f : s.mesh.faces()) {
    Vector3d c = Vector3d::Zero();
    for (auto v : s.mesh.fv_range(f)) c += sdm::point(s.mesh, v) / 3;
    const int expect = c.z() < 0 ? 0 : c.z() > 3 ? 2 : std::min(2, int(c.z() / 1.0));
    CHECK(fs[f.idx()] == expect);
  }
  const auto geo = sdm::segment_geometry(s.mesh, s.skeleton, fs);
  for (const auto& g : geo) {
    CHECK(g.radius == Approx(0.5).epsilon(0.01));
    CHECK(g.cap == Approx(M_PI * g.radius / 2));
    CHECK(g.length == Approx(1.0));
  }
}

TEST_CASE("layout: on a cylinder the STM coordinates are the capsule mapping, unwrapped at the seam", "[layout]") {
  const double r = 0.5, len = 3.0;
  const auto s = synth::capsule(r, len, 2, 64, 10, 30, 0.013);  // twisted: no vertex exactly on the seam
  const auto L = layout_of(s, 1024, 4, 0.0);  // one segment, not cut
  REQUIRE(L.segments.size() == 1);
  const auto& g = L.segments[0];
  CHECK(std::max(g.w, g.h) >= 1024 - 8 - 1);  // one rectangle spans the atlas
  const int seam = check_coordinates(s, L);
  CHECK(seam > 0);
  const auto c = sdm::stm_coordinates(s.mesh, L);
  CHECK(c.seam_faces == seam);
  CHECK(c.mesh.has_halfedge_texcoords2D());
  // Side of the cylinder: u linear in the angle from e1, v linear in z.
  std::vector<int> side;
  for (auto f : c.mesh.faces()) {
    bool on_side = true;
    for (auto h : c.mesh.fh_range(f)) {
      const Vector3d p = sdm::point(c.mesh, c.mesh.to_vertex_handle(h));
      on_side = on_side && p.z() > -1e-9 && p.z() < len + 1e-9;
      const auto& tc = c.mesh.texcoord2D(h);
      const Vector2d local = atlas_to_local(g, Vector2d(tc[0], tc[1]) * L.size);
      if (p.z() < -1e-9 || p.z() > len + 1e-9) continue;
      const Vector3d q = p - L.skeleton.nodes[g.a];
      double phi = std::atan2(q.dot(g.e2), q.dot(g.e1));
      if (phi < 0) phi += 2 * M_PI;
      const double u = g.h * phi / (2 * M_PI);
      const double du = std::remainder(local.x() - u, double(g.h));  // seam copies differ by h
      CHECK(std::abs(du) < 1e-6);
      const double t = (p - L.skeleton.nodes[g.a]).dot(g.axis) / len;
      CHECK(local.y() == Approx(g.d + t * (g.w - 2 * g.d)).margin(1e-6));
    }
    if (on_side) side.push_back(f.idx());
  }
  const double side_stretch = sdm::l2_stretch(c.mesh, side);
  INFO("L2 stretch on the side " << side_stretch << ", overall " << c.stretch);
  CHECK(side_stretch == Approx(1).epsilon(0.05));
  CHECK(c.stretch >= 1.0);
}

TEST_CASE("layout: chains, a Y and a torus keep every triangle in its own rectangle", "[layout]") {
  SECTION("chain") {
    const auto s = synth::capsule(0.4, 5.0, 6, 40, 6, 30, 0.0, 0.15);
    const auto L = layout_of(s, 512, 3);
    check_coordinates(s, L);
  }
  SECTION("Y") {
    const auto s = synth::ypsilon();
    const auto L = layout_of(s, 512, 3);
    // The Y is three capsules overlapping at the junction: their inner caps lie across the other
    // branches' axes.
    check_coordinates(s, L, [&](int f) {
      Vector3d c = Vector3d::Zero();
      for (auto v : s.mesh.fv_range(s.mesh.face_handle(f))) c += sdm::point(s.mesh, v) / 3;
      return c.norm() < 0.6;  // within the junction's ball of caps
    });
    for (const auto& g : L.segments) CHECK(g.neighbours_a.size() + g.neighbours_b.size() >= 1);
  }
  SECTION("torus") {
    const auto s = synth::torus(2.0, 0.5, 24);
    const auto L = layout_of(s);
    check_coordinates(s, L);
    INFO("torus coverage " << L.coverage);
    CHECK(L.coverage > 0.9);
    for (const auto& g : L.segments) {
      CHECK(g.neighbours_a.size() == 1);
      CHECK(g.neighbours_b.size() == 1);
      CHECK(g.radius == Approx(0.5).epsilon(0.02));
    }
    const auto c = sdm::stm_coordinates(s.mesh, L);
    INFO("torus stretch " << c.stretch);
    CHECK(c.stretch < 1.6);
  }
}

TEST_CASE("layout: JSON round trip, determinism and invariance under a rigid motion", "[layout]") {
  const auto s = synth::ypsilon();
  const auto L = layout_of(s, 512, 2);
  const auto j = sdm::layout_to_json(L);
  CHECK(j["format"] == "sdm-layout");
  CHECK(j["version"] == 1);
  const auto back = sdm::layout_from_json(nlohmann::json::parse(j.dump()));
  CHECK(sdm::layout_to_json(back) == j);
  CHECK(sdm::layout_to_json(layout_of(s, 512, 2)) == j);  // deterministic
  const auto c0 = sdm::stm_coordinates(s.mesh, L);
  const auto c1 = sdm::stm_coordinates(s.mesh, back);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(-1.3, Vector3d(0.3, -2, 1).normalized()).toRotationMatrix();
  const auto moved = synth::transformed(s, R, Vector3d(-4, 2, 7));
  const auto M = layout_of(moved, 512, 2);
  const auto c2 = sdm::stm_coordinates(moved.mesh, M);
  for (size_t i = 0; i < L.segments.size(); ++i) {
    CHECK(M.segments[i].x == L.segments[i].x);
    CHECK(M.segments[i].y == L.segments[i].y);
    CHECK(M.segments[i].w == L.segments[i].w);
    CHECK(M.segments[i].h == L.segments[i].h);
    CHECK(M.segments[i].rotated == L.segments[i].rotated);
  }
  double worst = 0, worst_back = 0;
  for (auto h : c0.mesh.halfedges()) {
    if (c0.mesh.is_boundary(h)) continue;
    const auto& a = c0.mesh.texcoord2D(h);
    const auto& b = c1.mesh.texcoord2D(h);
    const auto& m = c2.mesh.texcoord2D(h);
    worst_back = std::max(worst_back, (a - b).norm());
    worst = std::max(worst, (a - m).norm());
  }
  CHECK(worst_back == 0);
  CHECK(worst * L.size < 1e-6);  // texels
  CHECK(c2.stretch == Approx(c0.stretch).epsilon(1e-9));
}

TEST_CASE("layout: malformed layouts and mismatched skeletons are input errors", "[layout]") {
  const auto s = synth::capsule(0.5, 2.0, 3);
  auto j = sdm::layout_to_json(layout_of(s, 256, 2));
  auto bad = j;
  bad["format"] = "something";
  CHECK_THROWS_AS(sdm::layout_from_json(bad), sdm::InputError);
  bad = j;
  bad["segments"][0]["rect"] = {250, 250, 100, 100};
  CHECK_THROWS_AS(sdm::layout_from_json(bad), sdm::InputError);
  auto sk = s.skeleton;
  sk.vertex_node.pop_back();
  CHECK_THROWS_AS(sdm::compute_layout(s.mesh, sk), sdm::InputError);
}

TEST_CASE("layout: sdm stm writes the layout, the uv mesh and the atlas picture", "[layout]") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("sdm_test_layout_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto s = synth::torus(2.0, 0.6, 10, 48, 16);
  sdm::write_mesh(s.mesh, (dir / "torus.obj").string());
  sdm::write_skeleton_json(s.skeleton, (dir / "torus.skel.json").string());
  const std::string cmd = std::string(SDM_BINARY) + " stm " + (dir / "torus.obj").string() + " -o " + (dir / "torus.layout.json").string() +
                          " --skeleton " + (dir / "torus.skel.json").string() + " --size 256 --margin 2 --uv-obj " +
                          (dir / "torus_uv.obj").string() + " --atlas-png " + (dir / "atlas.png").string() + " --json 2>/dev/null";
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p);
  std::string out;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  CHECK(pclose(p) == 0);
  const auto j = nlohmann::json::parse(out);
  CHECK(j["segments"].get<int>() >= 10);  // the ring's 10 edges, maybe cut
  CHECK(j["coverage"].get<double>() > 0.5);
  CHECK(j["coverage"].get<double>() <= 1.0);
  CHECK(j["stretch"].get<double>() >= 1.0);
  CHECK(j["stretch"].get<double>() < 1.6);
  const auto L = sdm::read_layout_json((dir / "torus.layout.json").string());
  CHECK(L.segments.size() == j["segments"].get<size_t>());
  // Each rectangle says how far its capsule runs on past its nodes (a smooth ring: nowhere).
  for (size_t s = 0; s < L.segments.size(); ++s) {
    CHECK(j["rectangles"][s]["extend"][0].get<double>() == L.segments[s].extend_a);
    CHECK(j["rectangles"][s]["extend"][1].get<double>() == L.segments[s].extend_b);
  }
  const auto uv = sdm::load_mesh((dir / "torus_uv.obj").string()).mesh;
  CHECK(uv.n_faces() == s.mesh.n_faces());
  CHECK(fs::file_size(dir / "atlas.png") > 100);
  // Without --skeleton the command extracts one: the torus keeps its cycle.
  const std::string own = std::string(SDM_BINARY) + " stm " + (dir / "torus.obj").string() + " -o " +
                          (dir / "x.json").string() + " --size 256 --margin 2 2>/dev/null >/dev/null";
  const int rc = std::system(own.c_str());
  CHECK(WEXITSTATUS(rc) == 0);
  REQUIRE(fs::exists(dir / "x.json"));
  const auto X = sdm::read_layout_json((dir / "x.json").string());
  CHECK(X.skeleton.cycles() == 1);
  CHECK(X.coverage > 0.8);  // a 256^2 atlas with few segments
  // A missing mesh is an input error and leaves no output.
  const std::string refuse = std::string(SDM_BINARY) + " stm " + (dir / "missing.obj").string() + " -o " +
                             (dir / "y.json").string() + " 2>/dev/null";
  CHECK(WEXITSTATUS(std::system(refuse.c_str())) == 2);
  CHECK(!fs::exists(dir / "y.json"));
  fs::remove_all(dir);
}

TEST_CASE("layout: a straight tube cut into pieces keeps one frame and exact capsules", "[layout]") {
  // One edge 5 long on a tube of radius 0.4: cut into ceil(5 / (2 * 0.4)) = 7 pieces.
  const auto s = synth::capsule(0.4, 5.0, 2, 40, 6, 35);
  const auto L = layout_of(s, 1024, 4);
  REQUIRE(L.segments.size() == 7);
  for (const auto& g : L.segments) {
    CHECK(g.length == Approx(5.0 / 7).epsilon(1e-9));
    CHECK(g.radius == Approx(0.4).epsilon(0.02));
    CHECK(std::abs(g.axis.z()) == Approx(1).epsilon(1e-12));
    CHECK((g.e1 - L.segments[0].e1).norm() < 1e-9);  // the same reference direction everywhere
  }
  check_coordinates(s, L);
  const auto c = sdm::stm_coordinates(s.mesh, L);
  INFO("cut tube stretch " << c.stretch << " coverage " << L.coverage);
  CHECK(c.stretch < 1.1);
}

namespace {

// The atlas rectangles with their margins lie inside the atlas and do not overlap.
void check_packing(const sdm::Layout& L) {
  struct R {
    int x0, y0, x1, y1;
  };
  std::vector<R> rs;
  for (const auto& g : L.segments) {
    const int ex = g.rotated ? g.h : g.w, ey = g.rotated ? g.w : g.h;
    rs.push_back({g.x - L.margin, g.y - L.margin, g.x + ex + L.margin, g.y + ey + L.margin});
    CHECK(rs.back().x0 >= 0);
    CHECK(rs.back().y0 >= 0);
    CHECK(rs.back().x1 <= L.size);
    CHECK(rs.back().y1 <= L.size);
  }
  double area = 0;
  for (size_t i = 0; i < rs.size(); ++i) {
    area += double(rs[i].x1 - rs[i].x0) * (rs[i].y1 - rs[i].y0);
    for (size_t j = 0; j < i; ++j) {
      const bool apart = rs[i].x1 <= rs[j].x0 || rs[j].x1 <= rs[i].x0 || rs[i].y1 <= rs[j].y0 || rs[j].y1 <= rs[i].y0;
      CHECK(apart);
    }
  }
  CHECK(L.coverage == Approx(area / (double(L.size) * L.size)));
}

}  // namespace

TEST_CASE("layout: the paper's shapes and Spot with extracted skeletons cover the atlas as well as the paper", "[layout]") {
  // Paper Table II coverage; Spot is not in the table.
  const std::vector<std::pair<std::string, double>> shapes = {
      {"ypsilon", 0.837}, {"bottle", 0.894}, {"donut", 0.997}, {"triple-torus", 0.91}, {"crossed-cylinders", 0.743}, {"spot", 0.0}};
  for (const auto& [name, paper] : shapes) {
    const sdm::Mesh mesh = name == "spot" ? sdm::load_mesh(std::string(SDM_EXAMPLES) + "/spot/spot_triangulated.obj").mesh
                                          : sdm::make_primitive(name);
    const sdm::Skeleton sk = sdm::extract_skeleton(mesh);
    sdm::LayoutOptions o;  // 1024^2, margin 4
    const auto L = sdm::compute_layout(mesh, sk, o);
    const auto c = sdm::stm_coordinates(mesh, L);
    // Printed for every shape: the figures of Table II (docs/BENCHMARKS.md).
    std::printf("layout %-18s edges %2zu segments %2zu coverage %.3f (inner %.3f) L2 stretch %.3f\n", name.c_str(), sk.edges.size(),
                L.segments.size(), L.coverage, L.coverage_inner, c.stretch);
    INFO(name << ": coverage " << L.coverage << " stretch " << c.stretch);
    CHECK(L.coverage >= std::max(0.95, paper));  // 95 % on the paper's shapes (Table II)
    CHECK(L.coverage <= 1.0);
    check_packing(L);
    CHECK(c.stretch >= 1.0);
    // Spot's head is one junction with six short limbs (horns, ears, snout, neck): 1.93 before the
    // assignment's second pass, 1.19 now; the bound is 2 for every layout.
    CHECK(c.stretch < (name == "spot" ? 2.0 : 1.5));
    // Every vertex lies inside the rectangle of each segment that maps it.
    for (auto f : mesh.faces()) {
      const int s = c.face_segment[f.idx()];
      const auto& g = L.segments[s];
      for (auto v : mesh.fv_range(f)) {
        const auto q = sdm::capsule_uv(sdm::capsule_frame(L, s), g.w, g.h, g.d, sdm::point(mesh, v));
        CHECK(q.u >= 0);
        CHECK(q.u <= g.h);
        CHECK(q.v >= 0);
        CHECK(q.v <= g.w);
      }
    }
  }
}

namespace {

// Area-weighted L2 stretch and its 99th percentile by area, per face as l2_stretch measures it
// (Sander et al. 2001, the domain scaled to the surface's area).
std::pair<double, double> stretch_and_p99(const sdm::Mesh& m) {
  std::vector<std::pair<double, double>> face;  // squared stretch (unscaled), 3D area
  double A3 = 0, A2 = 0;
  for (auto f : m.faces()) {
    Vector3d q[3];
    Vector2d t[3];
    int k = 0;
    for (auto h : m.fh_range(f)) {
      q[k] = sdm::point(m, m.to_vertex_handle(h));
      t[k] = {m.texcoord2D(h)[0], m.texcoord2D(h)[1]};
      ++k;
    }
    const double a3 = 0.5 * (q[1] - q[0]).cross(q[2] - q[0]).norm();
    const double a2 = 0.5 * ((t[1] - t[0]).x() * (t[2] - t[0]).y() - (t[2] - t[0]).x() * (t[1] - t[0]).y());
    A3 += a3, A2 += std::abs(a2);
    if (a2 == 0) continue;
    const Vector3d Ss = (q[0] * (t[1].y() - t[2].y()) + q[1] * (t[2].y() - t[0].y()) + q[2] * (t[0].y() - t[1].y())) / (2 * a2);
    const Vector3d St = (q[0] * (t[2].x() - t[1].x()) + q[1] * (t[0].x() - t[2].x()) + q[2] * (t[1].x() - t[0].x())) / (2 * a2);
    face.emplace_back(0.5 * (Ss.squaredNorm() + St.squaredNorm()), a3);
  }
  const double norm = A2 / A3;
  double sum = 0;
  for (const auto& [s2, a] : face) sum += s2 * a;
  std::sort(face.begin(), face.end());
  double acc = 0, p99 = 0;
  for (const auto& [s2, a] : face) {
    acc += a;
    p99 = std::sqrt(s2 * norm);
    if (acc >= 0.99 * A3) break;
  }
  return {std::sqrt(sum / A3 * norm), p99};
}

}  // namespace

TEST_CASE("layout stretch of every closed mesh of ../shared/models is bounded", "[layout]") {
  // Before the assignment's second pass the L2 stretch was over 2 on bunny00 (14.0), the CAD parts
  // (6.0, 16.1) and every body (3.3-20.9): a few faces folded or mapped almost flat under their
  // segment's rectangle. The bounds are L2 <= 2 and p99 <= 4; bunny00's and anchor_dense's p99 were
  // 4.83 and 4.21 with the second pass alone (faces past a joint folded by every cap), 3.82 and 3.80
  // with the capsules extended at such joints (assign_faces, segments.h).
  const std::vector<test_util::SharedMesh> meshes = test_util::closed_shared_meshes();
  if (meshes.empty()) WARN("no meshes in ../shared/models: skipped");
  int extended = 0;
  for (const auto& sm : meshes) {
    const std::string& name = sm.name;
    const sdm::Mesh m = sdm::load_mesh(sm.path).mesh;
    const sdm::Layout L = sdm::compute_layout(m, sdm::extract_skeleton(m));
    const sdm::StmCoordinates c = sdm::stm_coordinates(m, L);
    const auto [l2, p99] = stretch_and_p99(c.mesh);
    INFO(name << ": L2 stretch " << l2 << " (reported " << c.stretch << "), p99 " << p99);
    CHECK(l2 == Approx(c.stretch).epsilon(1e-9));
    CHECK(l2 <= 2.0);
    CHECK(p99 <= 4.0);
    for (const auto& g : L.segments) extended += g.extend_a > 0 || g.extend_b > 0;
    // Written and read back, the layout assigns every face as it did (the shaders read the file).
    CHECK(sdm::assign_faces(m, sdm::layout_from_json(sdm::layout_to_json(L))) == c.face_segment);
    CHECK(L.assignment == (std::any_of(L.segments.begin(), L.segments.end(),
                                       [](const sdm::LayoutSegment& g) { return g.extend_a > 0 || g.extend_b > 0; })
                               ? 3
                               : 2));
  }
  if (!meshes.empty()) CHECK(extended > 0);  // bunny00 needs them
  // The paper's shapes need no extension: their layouts are those of the second pass alone.
  for (const std::string name : {"ypsilon", "bottle", "donut", "triple-torus", "crossed-cylinders"}) {
    const sdm::Mesh m = sdm::make_primitive(name);
    const sdm::Layout L = sdm::compute_layout(m, sdm::extract_skeleton(m));
    const auto [l2, p99] = stretch_and_p99(sdm::stm_coordinates(m, L).mesh);
    INFO(name << ": L2 stretch " << l2 << ", p99 " << p99);
    CHECK(l2 <= 2.0);
    CHECK(p99 <= 4.0);
    CHECK(L.assignment == 2);
  }
}
