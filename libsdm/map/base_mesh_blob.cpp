#include "libsdm/map/base_mesh_blob.h"

#include "libstm/core/errors.h"
#include "libstm/core/json_int.h"

#include <zlib.h>

#include <cstdint>
#include <map>
#include <tuple>

namespace sdm {
namespace {

const std::string kBad = "invalid base mesh in the SDM header: ";

// Deflate can shrink data by at most 1032:1; a claimed size beyond that is a damaged header.
constexpr double kMaxInflateRatio = 1032;

}  // namespace

std::string pack_base_mesh(const nlohmann::json& base) {
  const std::vector<int> tris = base.at("triangles").get<std::vector<int>>();
  const std::vector<double> uv = base.at("corner_uv").get<std::vector<double>>();
  const std::vector<double> d = base.contains("corner_d") ? base.at("corner_d").get<std::vector<double>>() : std::vector<double>();
  // One record per distinct (vertex, u, v, d) after rounding to float, numbered as first met.
  std::map<std::tuple<int, float, float, float>, int> index;
  std::vector<int> vertex, corner;
  std::vector<float> ruv, rd;
  for (size_t c = 0; c < tris.size(); ++c) {
    const auto key = std::make_tuple(tris[c], float(uv[2 * c]), float(uv[2 * c + 1]), d.empty() ? 0.0f : float(d[c]));
    auto [it, added] = index.emplace(key, int(vertex.size()));
    if (added) {
      vertex.push_back(tris[c]);
      ruv.push_back(std::get<1>(key)), ruv.push_back(std::get<2>(key));
      rd.push_back(std::get<3>(key));
    }
    corner.push_back(it->second);
  }
  nlohmann::json j = {{"vertex", vertex}, {"uv", ruv}, {"corner", corner}, {"face_segment", base.at("face_segment")}};
  if (!d.empty()) j["d"] = rd;
  if (base.contains("flat_faces")) j["flat_faces"] = base.at("flat_faces");
  const std::vector<uint8_t> cbor = nlohmann::json::to_cbor(j);
  uLongf packed = compressBound(uLong(cbor.size()));
  std::string out(8 + packed, '\0');
  const uint64_t n = cbor.size();
  for (int i = 0; i < 8; ++i) out[size_t(i)] = char((n >> (8 * i)) & 0xff);
  if (compress2(reinterpret_cast<Bytef*>(&out[8]), &packed, cbor.data(), uLong(cbor.size()), Z_BEST_COMPRESSION) != Z_OK)
    throw std::runtime_error("pack_base_mesh: zlib failed");
  out.resize(8 + packed);
  return out;
}

nlohmann::json unpack_base_mesh(const std::string& bytes) {
  if (bytes.size() < 9) throw InputError(kBad + "its " + std::to_string(bytes.size()) + " bytes are too few");
  uint64_t n = 0;
  for (int i = 0; i < 8; ++i) n |= uint64_t(uint8_t(bytes[size_t(i)])) << (8 * i);
  if (double(n) > kMaxInflateRatio * double(bytes.size() - 8) + 1024)
    throw InputError(kBad + "it claims " + std::to_string(n) + " bytes inflated from " + std::to_string(bytes.size() - 8));
  std::vector<uint8_t> cbor(static_cast<size_t>(n));
  uLongf got = uLongf(n);
  if (uncompress(cbor.data(), &got, reinterpret_cast<const Bytef*>(bytes.data() + 8), uLong(bytes.size() - 8)) != Z_OK || got != n)
    throw InputError(kBad + "its bytes do not inflate to the " + std::to_string(n) + " they claim");
  const nlohmann::json j = nlohmann::json::from_cbor(cbor, true, false);
  if (j.is_discarded() || !j.is_object()) throw InputError(kBad + "not a CBOR object");
  std::vector<int> vertex, corner;
  std::vector<double> uv, d;
  nlohmann::json face_segment;
  try {
    vertex = json_ints(j.at("vertex"));
    corner = json_ints(j.at("corner"));
    uv = j.at("uv").get<std::vector<double>>();
    if (j.contains("d")) d = j.at("d").get<std::vector<double>>();
    face_segment = j.at("face_segment");
  } catch (const nlohmann::json::exception& e) {
    throw InputError(kBad + e.what());
  }
  if (uv.size() != 2 * vertex.size() || (!d.empty() && d.size() != vertex.size()))
    throw InputError(kBad + std::to_string(vertex.size()) + " records but " + std::to_string(uv.size()) + " uv values and " +
                     std::to_string(d.size()) + " displacements");
  std::vector<int> tris;
  std::vector<double> cuv, cd;
  for (int r : corner) {
    if (r < 0 || size_t(r) >= vertex.size())
      throw InputError(kBad + "a corner names record " + std::to_string(r) + " of " + std::to_string(vertex.size()));
    tris.push_back(vertex[size_t(r)]);
    cuv.push_back(uv[2 * size_t(r)]), cuv.push_back(uv[2 * size_t(r) + 1]);
    if (!d.empty()) cd.push_back(d[size_t(r)]);
  }
  nlohmann::json out = {{"triangles", tris}, {"face_segment", face_segment}, {"corner_uv", cuv}};
  if (!d.empty()) out["corner_d"] = cd;
  if (j.contains("flat_faces")) out["flat_faces"] = j.at("flat_faces");
  return out;
}

}  // namespace sdm
