// glTF 2.0 input and output (libstm/mesh/gltf_io.h): round trips of Spot with its uv and texture,
// a cube split at its seams read back closed, node transforms, hostile files refused by name, and
// `sdm transfer -o OUT.glb` read back with its atlas. Every written .glb also passes
// check_glb_structure: the glTF validator's structural rules for a GLB, checked here (no
// validator is packaged in Debian): header and chunks, buffer views inside the buffer, accessors
// inside their views, POSITION's min/max equal to its values, indices inside the vertices,
// attribute counts equal, images PNG in a buffer view, every index to a texture, material, mesh,
// node valid.
#include "libstm/core/errors.h"
#include "libstm/core/image.h"
#include "libstm/mesh/gltf_io.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/validate_mesh.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cstring>
#include <functional>
#include <fstream>
#include <sstream>

namespace {

const std::string kSpot = std::string(SDM_EXAMPLES) + "/spot/spot_triangulated.obj";
const std::string kSpotTexture = std::string(SDM_EXAMPLES) + "/spot/spot_texture.png";

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

uint32_t u32(const std::string& b, size_t at) {
  uint32_t v = 0;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

size_t component_size(int type) {
  switch (type) {
    case 5120: case 5121: return 1;
    case 5122: case 5123: return 2;
    case 5125: case 5126: return 4;
    default: return 0;
  }
}

size_t type_components(const std::string& t) {
  if (t == "SCALAR") return 1;
  if (t == "VEC2") return 2;
  if (t == "VEC3") return 3;
  if (t == "VEC4") return 4;
  if (t == "MAT4") return 16;
  return 0;
}

// The structural rules above; returns the JSON chunk. REQUIREs fail the test on the first broken rule.
nlohmann::json check_glb_structure(const std::string& path) {
  const std::string b = read_bytes(path);
  REQUIRE(b.size() >= 28);
  REQUIRE(u32(b, 0) == 0x46546C67u);  // "glTF"
  REQUIRE(u32(b, 4) == 2u);
  REQUIRE(u32(b, 8) == b.size());
  const uint32_t json_length = u32(b, 12);
  REQUIRE(u32(b, 16) == 0x4E4F534Au);  // "JSON"
  REQUIRE(json_length % 4 == 0);
  REQUIRE(20 + json_length + 8 <= b.size());
  const nlohmann::json j = nlohmann::json::parse(b.substr(20, json_length));
  const size_t bin_at = 20 + json_length;
  const uint32_t bin_length = u32(b, bin_at);
  REQUIRE(u32(b, bin_at + 4) == 0x004E4942u);  // "BIN\0"
  REQUIRE(bin_at + 8 + bin_length == b.size());
  const std::string bin = b.substr(bin_at + 8, bin_length);
  REQUIRE(j.at("asset").at("version") == "2.0");
  REQUIRE(j.at("buffers").size() == 1);
  REQUIRE(j["buffers"][0].at("byteLength").get<size_t>() <= bin_length);
  for (const auto& v : j.at("bufferViews")) {
    REQUIRE(v.at("buffer") == 0);
    REQUIRE(v.value("byteOffset", size_t(0)) + v.at("byteLength").get<size_t>() <= j["buffers"][0]["byteLength"].get<size_t>());
  }
  const auto& views = j["bufferViews"];
  for (const auto& a : j.at("accessors")) {
    const auto& v = views.at(a.at("bufferView").get<size_t>());
    const size_t element = component_size(a.at("componentType")) * type_components(a.at("type"));
    REQUIRE(element > 0);
    REQUIRE(a.at("count").get<size_t>() > 0);
    REQUIRE(a.value("byteOffset", size_t(0)) + a["count"].get<size_t>() * element <= v["byteLength"].get<size_t>());
  }
  auto floats = [&](int accessor) {
    const auto& a = j["accessors"][accessor];
    const auto& v = views[a["bufferView"].get<size_t>()];
    std::vector<float> f(a["count"].get<size_t>() * type_components(a["type"]));
    std::memcpy(f.data(), bin.data() + v.value("byteOffset", size_t(0)) + a.value("byteOffset", size_t(0)), 4 * f.size());
    return f;
  };
  for (const auto& mesh : j.at("meshes"))
    for (const auto& p : mesh.at("primitives")) {
      const int pos = p.at("attributes").at("POSITION");
      const auto& pa = j["accessors"][pos];
      REQUIRE(pa.at("componentType") == 5126);
      const std::vector<float> x = floats(pos);
      for (int c = 0; c < 3; ++c) {
        float lo = INFINITY, hi = -INFINITY;
        for (size_t i = c; i < x.size(); i += 3) lo = std::min(lo, x[i]), hi = std::max(hi, x[i]);
        REQUIRE(pa.at("min")[c].get<float>() == lo);
        REQUIRE(pa.at("max")[c].get<float>() == hi);
      }
      for (const auto& [name, index] : p["attributes"].items()) REQUIRE(j["accessors"][index.get<int>()]["count"] == pa["count"]);
      const auto& ia = j["accessors"][p.at("indices").get<int>()];
      REQUIRE(ia.at("componentType") == 5125);
      const auto& iv = views[ia["bufferView"].get<size_t>()];
      for (size_t i = 0; i < ia["count"].get<size_t>(); ++i)
        REQUIRE(u32(bin, iv.value("byteOffset", size_t(0)) + 4 * i) < pa["count"].get<uint32_t>());
      if (p.contains("material")) REQUIRE(p["material"].get<size_t>() < j.at("materials").size());
    }
  for (const auto& m : j.value("materials", nlohmann::json::array()))
    if (m.at("pbrMetallicRoughness").contains("baseColorTexture"))
      REQUIRE(m["pbrMetallicRoughness"]["baseColorTexture"].at("index").get<size_t>() < j.at("textures").size());
  for (const auto& t : j.value("textures", nlohmann::json::array())) REQUIRE(t.at("source").get<size_t>() < j.at("images").size());
  for (const auto& im : j.value("images", nlohmann::json::array())) {
    REQUIRE(im.at("mimeType") == "image/png");
    const auto& v = views.at(im.at("bufferView").get<size_t>());
    REQUIRE(bin.compare(v.value("byteOffset", size_t(0)), 8, "\x89PNG\r\n\x1a\n") == 0);
  }
  for (const auto& n : j.at("nodes")) REQUIRE(n.at("mesh").get<size_t>() < j["meshes"].size());
  for (const auto& n : j.at("scenes")[0].at("nodes")) REQUIRE(n.get<size_t>() < j["nodes"].size());
  return j;
}

// A GLB of `json` and `bin` (both padded), for crafted files.
std::string make_glb(const nlohmann::json& json, std::string bin) {
  std::string text = json.dump();
  while (text.size() % 4) text += ' ';
  while (bin.size() % 4) bin += '\0';
  std::string out;
  auto put = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  put(0x46546C67u), put(2), put(uint32_t(12 + 8 + text.size() + 8 + bin.size()));
  put(uint32_t(text.size())), put(0x4E4F534Au);
  out += text;
  put(uint32_t(bin.size())), put(0x004E4942u);
  return out + bin;
}

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
  const sdm::Mesh spot = sdm::load_mesh(kSpot);
  REQUIRE(spot.has_halfedge_texcoords2D());
  const std::string glb = dir / "spot.glb";
  sdm::write_gltf(spot, glb, kSpotTexture);
  check_glb_structure(glb);
  sdm::Image embedded;
  const sdm::Mesh back = sdm::load_mesh(glb, nullptr, nullptr, &embedded);
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
  const sdm::Mesh back = sdm::load_mesh(dir / "out.glb", nullptr, nullptr, &embedded);
  const sdm::Mesh spot = sdm::load_mesh(kSpot);
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
  const sdm::Mesh back = sdm::load_mesh(dir / "spot.gltf");
  const sdm::Mesh spot = sdm::load_mesh(kSpot);
  CHECK(back.n_vertices() == spot.n_vertices());
  CHECK(back.n_faces() == spot.n_faces());
}

TEST_CASE("sdm render draws a .glb with its embedded texture as the OBJ with its PNG", "[gltf][render]") {
  test_util::TempDir dir;
  sdm::write_gltf(sdm::load_mesh(kSpot), dir / "spot.glb", kSpotTexture);
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
