#include "libstm/core/errors.h"
#include "libstm/mesh/isotropic_remesh.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/primitives.h"
#include "libstm/mesh/validate_mesh.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <sys/wait.h>

namespace {

double signed_volume(const sdm::Mesh& mesh) {
  double volume = 0;
  for (auto f : mesh.faces()) {
    auto it = mesh.cfv_begin(f);
    Eigen::Vector3d a = sdm::point(mesh, *it), b = sdm::point(mesh, *++it), c = sdm::point(mesh, *++it);
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

struct Expected {
  int genus;
  int vertices;
};
const std::map<std::string, Expected> kExpected = {
    {"ypsilon", {0, 480}},           {"bottle", {1, 1530}},  {"donut", {1, 1728}}, {"triple-torus", {3, 2256}},
    {"crossed-cylinders", {0, 3660}}, {"cylinder", {0, 1200}}, {"capsule", {0, 1200}}, {"two-tunnels", {2, 4000}},
    {"mushroom", {0, 3000}}};

}  // namespace

TEST_CASE("every primitive is a closed, outward, well-shaped 2-manifold of the paper's genus and size", "[primitives]") {
  REQUIRE(sdm::primitive_names().size() == kExpected.size());
  for (const auto& name : sdm::primitive_names()) {
    INFO(name);
    REQUIRE(kExpected.count(name) == 1);
    const Expected& e = kExpected.at(name);
    sdm::Mesh mesh = sdm::make_primitive(name);
    sdm::MeshReport r = sdm::validate_mesh(sdm::mesh_to_soup(mesh));
    CHECK(r.usable());
    CHECK(r.findings.empty());
    CHECK(r.boundary_loops == 0);
    REQUIRE(r.parts == 1);
    CHECK(r.genus_per_part[0] == e.genus);
    // Euler characteristic straight from the halfedge mesh as well.
    long chi = static_cast<long>(mesh.n_vertices()) - static_cast<long>(mesh.n_edges()) + static_cast<long>(mesh.n_faces());
    CHECK(chi == 2 - 2 * e.genus);
    CHECK(std::abs(static_cast<double>(mesh.n_vertices()) - e.vertices) <= 0.25 * e.vertices);
    CHECK(sdm::min_triangle_angle_degrees(mesh) > sdm::kPrimitiveMinAngleDegrees);
    CHECK(signed_volume(mesh) > 0);  // outward normals

    // Deterministic: a second call gives the very same mesh.
    sdm::Mesh again = sdm::make_primitive(name);
    REQUIRE(again.n_vertices() == mesh.n_vertices());
    REQUIRE(again.n_faces() == mesh.n_faces());
    bool same = true;
    for (auto v : mesh.vertices()) same = same && mesh.point(v) == again.point(v);
    for (auto f : mesh.faces()) {
      auto a = mesh.cfv_begin(f);
      auto b = again.cfv_begin(sdm::Mesh::FaceHandle(f.idx()));
      for (int k = 0; k < 3; ++k, ++a, ++b) same = same && a->idx() == b->idx();
    }
    CHECK(same);
  }
}

TEST_CASE("cylinder and capsule vertices lie on their analytic surfaces", "[primitives]") {
  // Cylinder: axis z, radius 1, z in [-1, 1], flat caps.
  sdm::Mesh cyl = sdm::make_primitive("cylinder");
  int side = 0, caps = 0;
  for (auto v : cyl.vertices()) {
    Eigen::Vector3d p = sdm::point(cyl, v);
    double rho = std::hypot(p.x(), p.y());
    bool on_side = std::abs(rho - 1) < 1e-9 && std::abs(p.z()) <= 1 + 1e-9;
    bool on_cap = std::abs(std::abs(p.z()) - 1) < 1e-9 && rho <= 1 + 1e-9;
    CHECK((on_side || on_cap));
    side += on_side && std::abs(p.z()) < 1 - 1e-9;
    caps += on_cap;
  }
  CHECK(side > 0);
  CHECK(caps > 0);
  // Inscribed polyhedron: slightly less than pi r^2 h = 2 pi.
  double v = signed_volume(cyl);
  CHECK(v < 2 * M_PI);
  CHECK(v > 0.99 * 2 * M_PI);

  // Capsule: the same cylinder closed by unit hemispheres centred at (0, 0, +-1).
  sdm::Mesh cap = sdm::make_primitive("capsule");
  for (auto vh : cap.vertices()) {
    Eigen::Vector3d p = sdm::point(cap, vh);
    double dist_to_axis_segment = (p - Eigen::Vector3d(0, 0, std::clamp(p.z(), -1.0, 1.0))).norm();
    CHECK(std::abs(dist_to_axis_segment - 1) < 1e-9);
  }
  double vc = signed_volume(cap);
  double exact = 2 * M_PI + 4.0 / 3.0 * M_PI;
  CHECK(vc < exact);
  CHECK(vc > 0.98 * exact);
}

TEST_CASE("the donut is a torus of radii 1 and 0.4", "[primitives]") {
  sdm::Mesh donut = sdm::make_primitive("donut");
  for (auto v : donut.vertices()) {
    Eigen::Vector3d p = sdm::point(donut, v);
    CHECK(std::abs(std::hypot(std::hypot(p.x(), p.y()) - 1.0, p.z()) - 0.4) < 1e-9);
  }
  double exact = 2 * M_PI * M_PI * 1.0 * 0.4 * 0.4;
  CHECK(signed_volume(donut) < exact);
  CHECK(signed_volume(donut) > 0.98 * exact);
}

TEST_CASE("resolution is an approximate vertex count and keeps shape and topology", "[primitives]") {
  for (const auto& [name, target] : std::vector<std::pair<std::string, int>>{{"ypsilon", 1500}, {"donut", 5000}, {"capsule", 400}}) {
    INFO(name << " at " << target);
    sdm::Mesh mesh = sdm::make_primitive(name, target);
    sdm::MeshReport r = sdm::validate_mesh(sdm::mesh_to_soup(mesh));
    CHECK(r.usable());
    REQUIRE(r.parts == 1);
    CHECK(r.genus_per_part[0] == kExpected.at(name).genus);
    CHECK(std::abs(static_cast<double>(mesh.n_vertices()) - target) <= 0.1 * target);
    CHECK(sdm::min_triangle_angle_degrees(mesh) > sdm::kPrimitiveMinAngleDegrees);
  }
  // Both ypsilons are inscribed in the same surface: the finer one holds more volume, and the
  // coarse one (about 13 edges around a tube) misses at most what a 13-gon misses of its circle,
  // 1 - 13 sin(2 pi / 13) / (2 pi) = 3.9 %.
  double coarse = signed_volume(sdm::make_primitive("ypsilon")), fine = signed_volume(sdm::make_primitive("ypsilon", 3000));
  CHECK(fine > coarse);
  CHECK(fine - coarse < 0.045 * fine);
}

TEST_CASE("unknown primitive names and bad resolutions are input errors", "[primitives]") {
  try {
    sdm::make_primitive("teapot");
    FAIL("no exception");
  } catch (const sdm::InputError& e) {
    std::string what = e.what();
    CHECK(what.find("teapot") != std::string::npos);
    for (const auto& n : sdm::primitive_names()) CHECK(what.find(n) != std::string::npos);
  }
  CHECK_THROWS_AS(sdm::make_primitive("donut", 10), sdm::InputError);
  CHECK_THROWS_AS(sdm::make_primitive("donut", -5), sdm::InputError);
}

TEST_CASE("sdm primitive writes a mesh that loads back with the same counts", "[primitives]") {
  const std::string out = "test_primitives_bottle.ply", json = "test_primitives_bottle.json";
  std::remove(out.c_str());
  std::string cmd = std::string("\"") + SDM_BINARY + "\" primitive bottle -o " + out + " --json > " + json;
  REQUIRE(std::system(cmd.c_str()) == 0);
  std::ifstream in(json);
  nlohmann::json j = nlohmann::json::parse(in);
  sdm::Mesh expected = sdm::make_primitive("bottle");
  sdm::Mesh loaded = sdm::load_mesh(out).mesh;
  CHECK(loaded.n_vertices() == expected.n_vertices());
  CHECK(loaded.n_faces() == expected.n_faces());
  CHECK(j["vertices"].get<long>() == static_cast<long>(expected.n_vertices()));
  CHECK(j["faces"].get<long>() == static_cast<long>(expected.n_faces()));
  CHECK(j["genus"].get<int>() == 1);

  // Unknown names exit with code 2 (bad input).
  std::string bad = std::string("\"") + SDM_BINARY + "\" primitive teapot -o x.obj 2> /dev/null";
  int status = std::system(bad.c_str());
  CHECK(WEXITSTATUS(status) == 2);
  std::remove(out.c_str());
  std::remove(json.c_str());
}
