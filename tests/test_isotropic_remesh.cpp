// Isotropic remeshing of real meshes through `sdm remesh`: new triangles, same surface and genus.
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/surface_distance.h"
#include "libstm/mesh/isotropic_remesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/validate_mesh.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>

using namespace sdm;

TEST_CASE("sdm remesh keeps the surface and the genus with a new tessellation", "[isotropic_remesh]") {
  test_util::TempDir dir;
  // An organic blob and a thin-walled CAD ring of genus 1 with long sliver triangles.
  // Thin walls need edges well below their thickness (see sdm remesh --help): the ring gets 0.3.
  struct Case {
    const char* name;
    int genus;
    const char* factor;
  };
  for (const Case& c : {Case{"blobby.off", 0, "0.8"}, Case{"rotor.off", 1, "0.3"}}) {
  const char* name = c.name;
  const int genus = c.genus;
  INFO(name);
  const std::string in = std::string(SDM_TEST_DATA) + "/" + name;
  auto r = test_util::run_sdm("remesh " + in + " -o " + (dir / "out.ply") + " --factor " + c.factor);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const Mesh a = load_mesh(in).mesh, b = load_mesh(dir / "out.ply").mesh;
  CHECK(b.n_vertices() != a.n_vertices());
  const MeshReport rep = validate_mesh(mesh_to_soup(b));
  CHECK(rep.usable());
  CHECK(rep.genus_per_part == std::vector<int>{genus});
  CHECK(min_triangle_angle_degrees(b) > 20.0);
  const SurfaceDistance d = surface_distance(a, b, 20000);
  INFO("hausdorff " << d.hausdorff / d.diagonal);
  // No feature preservation: sharp creases are rounded by up to about one edge length.
  double edge = 0;
  for (auto e : b.edges()) edge += b.calc_edge_length(e);
  edge /= double(b.n_edges());
  CHECK(d.hausdorff < edge);
  CHECK(d.rms / d.diagonal < 0.005);
  }
  CHECK(test_util::run_sdm("remesh " + (dir / "missing.off") + " -o " + (dir / "x.obj")).exit_code == 2);
}
