#include "libstm/atomic_file.h"
#include "libstm/errors.h"
#include "libstm/layout.h"
#include "libstm/segments.h"
#include "synthetic_shapes.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <sys/wait.h>
#include <unistd.h>

using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

// Atlas texels -> local (u, v) of segment g.
Vector2d atlas_to_local(const stm::LayoutSegment& g, const Vector2d& a) {
  return g.rotated ? Vector2d(a.x() - g.x, a.y() - g.y) : Vector2d(a.y() - g.y, a.x() - g.x);
}

// Checks what every layout must satisfy on a mesh; returns the number of seam faces. `skip_span`
// names faces exempt from the half-rectangle span check (faces around a junction that lie across
// another segment's axis can span any angle).
int check_coordinates(const synth::Shape& s, const stm::Layout& L, const std::function<bool(int)>& skip_span = {}) {
  const auto fs = stm::assign_faces(s.mesh, s.skeleton);
  const auto tris = stm::atlas_triangles(s.mesh, L, fs);
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
      const auto c = stm::capsule_uv(stm::capsule_frame(L, seg), g.w, g.h, g.d, stm::point(s.mesh, v));
      CHECK(c.u >= 0);
      CHECK(c.u <= g.h);
      CHECK(c.v >= 0);
      CHECK(c.v <= g.w);
    }
  }
  return seam;
}

stm::Layout layout_of(const synth::Shape& s, int size = 1024, int margin = 4) {
  stm::LayoutOptions o;
  o.size = size;
  o.margin = margin;
  return stm::compute_layout(s.mesh, s.skeleton, o);
}

}  // namespace

TEST_CASE("layout: segments of a chain get their own faces, radius and cap", "[layout]") {
  const auto s = synth::capsule(0.5, 3.0, 4, 64, 10, 30);
  const auto fs = stm::assign_faces(s.mesh, s.skeleton);
  // Faces over the cylinder part go to the segment they lie over; the caps to the end segments.
  for (auto f : s.mesh.faces()) {
    Vector3d c = Vector3d::Zero();
    for (auto v : s.mesh.fv_range(f)) c += stm::point(s.mesh, v) / 3;
    const int expect = c.z() < 0 ? 0 : c.z() > 3 ? 2 : std::min(2, int(c.z() / 1.0));
    CHECK(fs[f.idx()] == expect);
  }
  const auto geo = stm::segment_geometry(s.mesh, s.skeleton, fs);
  for (const auto& g : geo) {
    CHECK(g.radius == Approx(0.5).epsilon(0.01));
    CHECK(g.cap == Approx(M_PI * g.radius / 2));
    CHECK(g.length == Approx(1.0));
  }
}

TEST_CASE("layout: on a cylinder the STM coordinates are the capsule mapping, unwrapped at the seam", "[layout]") {
  const double r = 0.5, len = 3.0;
  const auto s = synth::capsule(r, len, 2, 64, 10, 30, 0.013);  // twisted: no vertex exactly on the seam
  const auto L = layout_of(s);
  REQUIRE(L.segments.size() == 1);
  const auto& g = L.segments[0];
  CHECK(std::max(g.w, g.h) >= 1024 - 8 - 1);  // one rectangle spans the atlas
  const int seam = check_coordinates(s, L);
  CHECK(seam > 0);
  const auto c = stm::stm_coordinates(s.mesh, L);
  CHECK(c.seam_faces == seam);
  CHECK(c.mesh.has_halfedge_texcoords2D());
  // Side of the cylinder: u linear in the angle from e1, v linear in z.
  std::vector<int> side;
  for (auto f : c.mesh.faces()) {
    bool on_side = true;
    for (auto h : c.mesh.fh_range(f)) {
      const Vector3d p = stm::point(c.mesh, c.mesh.to_vertex_handle(h));
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
  const double side_stretch = stm::l2_stretch(c.mesh, side);
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
      for (auto v : s.mesh.fv_range(s.mesh.face_handle(f))) c += stm::point(s.mesh, v) / 3;
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
    const auto c = stm::stm_coordinates(s.mesh, L);
    INFO("torus stretch " << c.stretch);
    CHECK(c.stretch < 1.6);
  }
}

TEST_CASE("layout: JSON round trip, determinism and invariance under a rigid motion", "[layout]") {
  const auto s = synth::ypsilon();
  const auto L = layout_of(s, 512, 2);
  const auto j = stm::layout_to_json(L);
  CHECK(j["format"] == "sdm-layout");
  CHECK(j["version"] == 1);
  const auto back = stm::layout_from_json(nlohmann::json::parse(j.dump()));
  CHECK(stm::layout_to_json(back) == j);
  CHECK(stm::layout_to_json(layout_of(s, 512, 2)) == j);  // deterministic
  const auto c0 = stm::stm_coordinates(s.mesh, L);
  const auto c1 = stm::stm_coordinates(s.mesh, back);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(-1.3, Vector3d(0.3, -2, 1).normalized()).toRotationMatrix();
  const auto moved = synth::transformed(s, R, Vector3d(-4, 2, 7));
  const auto M = layout_of(moved, 512, 2);
  const auto c2 = stm::stm_coordinates(moved.mesh, M);
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
  auto j = stm::layout_to_json(layout_of(s, 256, 2));
  auto bad = j;
  bad["format"] = "something";
  CHECK_THROWS_AS(stm::layout_from_json(bad), stm::InputError);
  bad = j;
  bad["segments"][0]["rect"] = {250, 250, 100, 100};
  CHECK_THROWS_AS(stm::layout_from_json(bad), stm::InputError);
  auto sk = s.skeleton;
  sk.vertex_node.pop_back();
  CHECK_THROWS_AS(stm::compute_layout(s.mesh, sk), stm::InputError);
}

TEST_CASE("layout: sdm stm writes the layout, the uv mesh and the atlas picture", "[layout]") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("sdm_test_layout_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto s = synth::torus(2.0, 0.6, 10, 48, 16);
  stm::write_mesh(s.mesh, (dir / "torus.obj").string());
  stm::write_skeleton_json(s.skeleton, (dir / "torus.skel.json").string());
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
  CHECK(j["segments"] == 10);
  CHECK(j["coverage"].get<double>() > 0.5);
  CHECK(j["coverage"].get<double>() <= 1.0);
  CHECK(j["stretch"].get<double>() >= 1.0);
  CHECK(j["stretch"].get<double>() < 1.6);
  const auto L = stm::read_layout_json((dir / "torus.layout.json").string());
  CHECK(L.segments.size() == 10);
  const auto uv = stm::load_mesh((dir / "torus_uv.obj").string());
  CHECK(uv.n_faces() == s.mesh.n_faces());
  CHECK(fs::file_size(dir / "atlas.png") > 100);
  // Without a skeleton the command refuses with the input-error code.
  const std::string refuse = std::string(SDM_BINARY) + " stm " + (dir / "torus.obj").string() + " -o " +
                             (dir / "x.json").string() + " 2>/dev/null";
  const int rc = std::system(refuse.c_str());
  CHECK(WEXITSTATUS(rc) == 2);
  CHECK(!fs::exists(dir / "x.json"));
  fs::remove_all(dir);
}
