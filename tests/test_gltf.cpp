// glTF 2.0 input and output (libstm/mesh/gltf_io.h): round trips of Spot with its uv and texture,
// a cube split at its seams read back closed, node transforms, hostile files refused by name, and
// `sdm transfer -o OUT.glb` read back with its atlas. Every written .glb also passes
// check_glb_structure (tests/glb_check.h): the glTF validator's structural rules for a GLB.
#include "libstm/core/errors.h"
#include "libstm/core/image.h"
#include "libstm/mesh/gltf_io.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/validate_mesh.h"
#include "tests/glb_check.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cstring>
#include <functional>

namespace {

using namespace glb_check;

const std::string kSpot = std::string(SDM_EXAMPLES) + "/spot/spot_triangulated.obj";
const std::string kSpotTexture = std::string(SDM_EXAMPLES) + "/spot/spot_texture.png";

// A unit cube as glTF writes a hard-edged one: 4 vertices per side (24), 12 triangles, in a node
// translated by (10, 0, 0) and scaled by 2.
// `edit` changes the JSON before it is packed (hostile variants); `colors`: a COLOR_0 too, each
// vertex's (linear) colour half its position in the unit cube.
std::string split_cube_glb(size_t count_override = 0, const std::function<void(nlohmann::json&)>& edit = {}, bool colors = false) {
  std::vector<float> p;
  std::vector<uint32_t> idx;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const uint32_t base = uint32_t(p.size() / 3);
      for (int k = 0; k < 4; ++k) {
        float x[3];
        x[axis] = float(side);
        x[(axis + 1) % 3] = float(k & 1);
        x[(axis + 2) % 3] = float(k >> 1);
        p.insert(p.end(), x, x + 3);
      }
      // outward orientation: (axis+1, axis+2) is right-handed about +axis
      if (side) idx.insert(idx.end(), {base, base + 1, base + 3, base, base + 3, base + 2});
      else idx.insert(idx.end(), {base, base + 3, base + 1, base, base + 2, base + 3});
    }
  std::string bin(reinterpret_cast<const char*>(p.data()), 4 * p.size());
  bin.append(reinterpret_cast<const char*>(idx.data()), 4 * idx.size());
  std::vector<float> c;
  for (float x : p) c.push_back(0.5f * x);
  if (colors) bin.append(reinterpret_cast<const char*>(c.data()), 4 * c.size());
  nlohmann::json j = {
      {"asset", {{"version", "2.0"}}},
      {"buffers", {{{"byteLength", bin.size()}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 4 * p.size()}},
                       {{"buffer", 0}, {"byteOffset", 4 * p.size()}, {"byteLength", 4 * idx.size()}}}},
      {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"type", "VEC3"}, {"count", count_override ? count_override : 24},
                      {"min", {0, 0, 0}}, {"max", {1, 1, 1}}},
                     {{"bufferView", 1}, {"componentType", 5125}, {"type", "SCALAR"}, {"count", 36}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
      {"nodes", {{{"mesh", 0}, {"translation", {10, 0, 0}}, {"scale", {2, 2, 2}}}}},
      {"scenes", {{{"nodes", {0}}}}},
      {"scene", 0}};
  if (colors) {
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 4 * (p.size() + idx.size())}, {"byteLength", 4 * c.size()}});
    j["accessors"].push_back({{"bufferView", 2}, {"componentType", 5126}, {"type", "VEC3"}, {"count", 24}});
    j["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = 2;
  }
  if (edit) edit(j);
  return make_glb(j, bin);
}

}  // namespace

TEST_CASE("Spot written as .glb reads back with the same points, faces, uv and texture", "[gltf]") {
  test_util::TempDir dir;
  const sdm::Mesh spot = sdm::load_mesh(kSpot).mesh;
  REQUIRE(spot.has_halfedge_texcoords2D());
  const std::string glb = dir / "spot.glb";
  sdm::write_gltf(spot, glb, kSpotTexture);
  check_glb_structure(glb);
  sdm::Image embedded;
  sdm::LoadedMesh back_read = sdm::load_mesh(glb);
  embedded = std::move(back_read.texture_image);
  const sdm::Mesh back = std::move(back_read.mesh);
  REQUIRE(back.n_vertices() == spot.n_vertices());
  REQUIRE(back.n_faces() == spot.n_faces());
  REQUIRE(back.has_halfedge_texcoords2D());
  // Face f is face f; its corners may start elsewhere: each is paired with the nearest corner.
  double position = 0, uv = 0;
  for (auto f : spot.faces())
    for (auto h : spot.fh_range(f)) {
      double best = INFINITY, best_uv = INFINITY;
      for (auto hb : back.fh_range(back.face_handle(f.idx()))) {
        const double d = (sdm::point(spot, spot.to_vertex_handle(h)) - sdm::point(back, back.to_vertex_handle(hb))).norm();
        if (d < best) best = d, best_uv = double((spot.texcoord2D(h) - back.texcoord2D(hb)).norm());
      }
      position = std::max(position, best);
      uv = std::max(uv, best_uv);
    }
  INFO("largest position change " << position << ", uv change " << uv);
  CHECK(position < 1e-6);  // float32 in the file
  CHECK(uv < 1e-6);
  const sdm::Image png = sdm::read_png(kSpotTexture);
  REQUIRE(embedded.width == png.width);
  REQUIRE(embedded.height == png.height);
  long differ = 0;
  for (int y = 0; y < png.height; ++y)
    for (int x = 0; x < png.width; ++x)
      for (int c = 0; c < 3; ++c) differ += embedded.at(x, y)[c] != png.at(x, y)[c];
  CHECK(differ == 0);
}

TEST_CASE("A glTF cube split at its seams reads back closed, placed by its node", "[gltf]") {
  test_util::TempDir dir;
  test_util::write_file(dir / "cube.glb", split_cube_glb());
  const sdm::MeshSoup soup = sdm::read_mesh_soup(dir / "cube.glb");
  CHECK(soup.points.size() == 8);  // 24 glTF vertices welded by position
  CHECK(soup.triangles.size() == 12);
  const sdm::MeshReport report = sdm::validate_mesh(soup);
  CHECK(report.usable());
  CHECK(report.boundary_loops == 0);
  CHECK(report.bbox_min.isApprox(Eigen::Vector3d(10, 0, 0)));
  CHECK(report.bbox_max.isApprox(Eigen::Vector3d(12, 2, 2)));
}

TEST_CASE("A glTF's COLOR_0 reads as the vertices' colours, turned from linear to sRGB", "[gltf]") {
  test_util::TempDir dir;
  test_util::write_file(dir / "cube.glb", split_cube_glb(0, {}, true));
  const sdm::MeshSoup soup = sdm::read_mesh_soup(dir / "cube.glb");
  REQUIRE(soup.points.size() == 8);
  REQUIRE(soup.colors.size() == 8);
  const float srgb_half = float(1.055 * std::pow(0.5, 1 / 2.4) - 0.055);  // 0.7354
  for (size_t v = 0; v < 8; ++v) {
    const Eigen::Vector3d corner = (soup.points[v] - Eigen::Vector3d(10, 0, 0)) / 2;  // the node's placement undone
    for (int k = 0; k < 3; ++k) CHECK(soup.colors[v][k] == Approx(corner[k] > 0.5 ? srgb_half : 0.0f).margin(1e-6));
  }
}

TEST_CASE("Hostile glTF files are refused by name", "[gltf][hostile]") {
  test_util::TempDir dir;
  SECTION("an accessor counting more vertices than its buffer holds") {
    test_util::write_file(dir / "long.glb", split_cube_glb(2000000000));
    const auto r = test_util::run_sdm("info " + dir / "long.glb");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("reaches outside its buffer") != std::string::npos);
  }
  SECTION("a node reached twice (nodes form a tree), which would instance its subtree exponentially") {
    test_util::write_file(dir / "dag.glb", split_cube_glb(0, [](nlohmann::json& j) {
      j["nodes"] = {{{"mesh", 0}}, {{"children", {0, 0}}}, {{"children", {1, 1}}}};
      j["scenes"][0]["nodes"] = {2};
    }));
    const auto r = test_util::run_sdm("info " + dir / "dag.glb");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("reached twice") != std::string::npos);
  }
  SECTION("a node scale that throws the vertices beyond the float range") {
    test_util::write_file(dir / "far.glb", split_cube_glb(0, [](nlohmann::json& j) { j["nodes"][0]["scale"] = {1e300, 1, 1}; }));
    const auto r = test_util::run_sdm("info " + dir / "far.glb");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("beyond the float range") != std::string::npos);
  }
  SECTION("a truncated file") {
    const std::string whole = split_cube_glb();
    test_util::write_file(dir / "cut.glb", whole.substr(0, whole.size() - 40));
    const auto r = test_util::run_sdm("info " + dir / "cut.glb");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("cannot read glTF") != std::string::npos);
  }
  SECTION("JSON that is no glTF") {
    test_util::write_file(dir / "x.gltf", "{\"asset\": 3}");
    const auto r = test_util::run_sdm("info " + dir / "x.gltf");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("glTF") != std::string::npos);
  }
}

TEST_CASE("sdm transfer -o OUT.glb writes the target with its uv and the atlas embedded", "[gltf][transfer_texture]") {
  test_util::TempDir dir;
  const auto r = test_util::run_sdm("transfer --source " + kSpot + " --texture " + kSpotTexture + " --target " + kSpot + " -o " +
                                    dir / "out.glb --size 512");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const nlohmann::json j = check_glb_structure(dir / "out.glb");
  CHECK(j.at("images").size() == 1);
  sdm::Image embedded;
  sdm::LoadedMesh back_read = sdm::load_mesh(dir / "out.glb");
  embedded = std::move(back_read.texture_image);
  const sdm::Mesh back = std::move(back_read.mesh);
  const sdm::Mesh spot = sdm::load_mesh(kSpot).mesh;
  CHECK(back.n_vertices() == spot.n_vertices());
  CHECK(back.has_halfedge_texcoords2D());
  const sdm::Image atlas = sdm::read_png(dir / "out_atlas.png");
  REQUIRE(embedded.width == 512);
  REQUIRE(embedded.height == 512);
  CHECK(embedded.pixels == atlas.pixels);
  // The glb's uv address the atlas: every corner inside [0, 1] once wrapped, none NaN.
  long outside = 0;
  for (auto h : back.halfedges())
    if (!back.is_boundary(h) && !(std::isfinite(back.texcoord2D(h)[0]) && std::isfinite(back.texcoord2D(h)[1]))) ++outside;
  CHECK(outside == 0);
}

TEST_CASE("sdm convert writes .gltf with embedded buffers that reads back as the input", "[gltf]") {
  test_util::TempDir dir;
  const auto r = test_util::run_sdm("convert " + kSpot + " -o " + dir / "spot.gltf");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const nlohmann::json j = nlohmann::json::parse(read_bytes(dir / "spot.gltf"));
  CHECK(j.at("buffers")[0].at("uri").get<std::string>().rfind("data:application/octet-stream;base64,", 0) == 0);
  const sdm::Mesh back = sdm::load_mesh(dir / "spot.gltf").mesh;
  const sdm::Mesh spot = sdm::load_mesh(kSpot).mesh;
  CHECK(back.n_vertices() == spot.n_vertices());
  CHECK(back.n_faces() == spot.n_faces());
}

TEST_CASE("sdm render draws a .glb with its embedded texture as the OBJ with its PNG", "[gltf][render]") {
  test_util::TempDir dir;
  sdm::write_gltf(sdm::load_mesh(kSpot).mesh, dir / "spot.glb", kSpotTexture);
  const auto a = test_util::run_sdm("render " + dir / "spot.glb" + " --unlit --width 256 --height 256 -o " + dir / "glb.png");
  const auto b = test_util::run_sdm("render " + kSpot + " --texture " + kSpotTexture + " --unlit --width 256 --height 256 -o " + dir / "obj.png");
  INFO(a.output << b.output);
  REQUIRE(a.exit_code == 0);
  REQUIRE(b.exit_code == 0);
  const sdm::Image ia = sdm::read_png(dir / "glb.png"), ib = sdm::read_png(dir / "obj.png");
  REQUIRE(ia.pixels.size() == ib.pixels.size());
  double diff = 0;
  long textured = 0;  // pixels neither background nor the flat colour: the texture is drawn
  for (size_t i = 0; i < ia.pixels.size(); ++i) diff += std::abs(int(ia.pixels[i]) - int(ib.pixels[i]));
  for (int y = 0; y < ia.height; ++y)
    for (int x = 0; x < ia.width; ++x)
      if (ia.at(x, y)[0] != ia.at(0, 0)[0] || ia.at(x, y)[1] != ia.at(0, 0)[1]) ++textured;
  diff /= double(ia.pixels.size());
  INFO("mean absolute difference " << diff << " of 255, " << textured << " object pixels");
  CHECK(diff < 1.0);
  CHECK(textured > 5000);
}
