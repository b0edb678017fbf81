#pragma once
// Checks of written .glb files shared by the glTF tests (test_gltf.cpp, test_gltf_skin.cpp): the
// glTF validator's structural rules, and crafted GLB files.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace glb_check {

inline std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline uint32_t u32(const std::string& b, size_t at) {
  uint32_t v = 0;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

inline size_t component_size(int type) {
  switch (type) {
    case 5120: case 5121: return 1;
    case 5122: case 5123: return 2;
    case 5125: case 5126: return 4;
    default: return 0;
  }
}

inline size_t type_components(const std::string& t) {
  if (t == "SCALAR") return 1;
  if (t == "VEC2") return 2;
  if (t == "VEC3") return 3;
  if (t == "VEC4") return 4;
  if (t == "MAT4") return 16;
  return 0;
}

// The glTF validator's structural rules for a GLB (no validator is packaged in Debian): header and
// chunks, buffer views inside the buffer, accessors inside their views, POSITION's min/max equal to
// its values, indices inside the vertices, attribute counts equal, images PNG in a buffer view,
// every index to a texture, material, mesh, skin, node valid. Returns the JSON chunk. REQUIREs fail the test on the first broken rule.
inline nlohmann::json check_glb_structure(const std::string& path) {
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
  for (const auto& n : j.at("nodes")) {
    if (n.contains("mesh")) REQUIRE(n["mesh"].get<size_t>() < j["meshes"].size());
    if (n.contains("skin")) REQUIRE(n["skin"].get<size_t>() < j.at("skins").size());
    for (const auto& c : n.value("children", nlohmann::json::array())) REQUIRE(c.get<size_t>() < j["nodes"].size());
  }
  for (const auto& n : j.at("scenes")[0].at("nodes")) REQUIRE(n.get<size_t>() < j["nodes"].size());
  return j;
}

// A GLB of `json` and `bin` (both padded), for crafted files.
inline std::string make_glb(const nlohmann::json& json, std::string bin) {
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

// A GLB's two chunks, for checks that read the binary data.
struct Glb {
  nlohmann::json json;
  std::string bin;
};

inline Glb read_glb(const std::string& path) {
  const std::string b = read_bytes(path);
  REQUIRE(b.size() >= 28);
  const uint32_t json_length = u32(b, 12);
  REQUIRE(20 + json_length + 8 <= b.size());
  return {nlohmann::json::parse(b.substr(20, json_length)), b.substr(20 + json_length + 8)};
}

// The components of accessor `index`, element after element, as doubles (normalized integers
// mapped to [0, 1]); honours the view's byteStride.
inline std::vector<double> accessor_values(const Glb& g, int index) {
  const auto& a = g.json.at("accessors").at(index);
  const auto& v = g.json.at("bufferViews").at(a.at("bufferView").get<size_t>());
  const int type = a.at("componentType");
  const size_t size = component_size(type), n = type_components(a.at("type")), count = a.at("count");
  const size_t stride = v.value("byteStride", size * n);
  const bool normalized = a.value("normalized", false);
  const size_t at = v.value("byteOffset", size_t(0)) + a.value("byteOffset", size_t(0));
  REQUIRE(at + (count - 1) * stride + size * n <= g.bin.size());
  std::vector<double> out;
  for (size_t i = 0; i < count; ++i)
    for (size_t c = 0; c < n; ++c) {
      const char* p = g.bin.data() + at + i * stride + c * size;
      if (type == 5126) {
        float f;
        std::memcpy(&f, p, 4);
        out.push_back(f);
      } else if (type == 5121) {
        out.push_back(normalized ? uint8_t(*p) / 255.0 : uint8_t(*p));
      } else if (type == 5123) {
        uint16_t x;
        std::memcpy(&x, p, 2);
        out.push_back(normalized ? x / 65535.0 : x);
      } else {
        uint32_t x;
        std::memcpy(&x, p, 4);
        out.push_back(x);
      }
    }
  return out;
}

}  // namespace glb_check
