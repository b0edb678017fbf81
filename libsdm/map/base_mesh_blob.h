#pragma once
/// The base mesh of an SDM header in binary (format version 3). The JSON object that
/// base_mesh_to_json writes ("triangles", "face_segment", "corner_uv", "corner_d") printed 17
/// digits per number, more than a whole compact map may take (docs/BENCHMARKS.md). Here each
/// distinct corner record (vertex, u, v, d) is stored once (the corners of one vertex in one segment
/// share it; they differ only across a capsule's seam or between segments), the numbers as 32-bit
/// floats (a 1e-7 relative error: 1e-4 texel on a 1000-texel rectangle), and the whole as CBOR
/// (nlohmann::json) deflated by zlib.
#include <nlohmann/json.hpp>
#include <string>

namespace sdm {

/// base_mesh: the JSON object of base_mesh_to_json. Returns the bytes for the header attribute.
std::string pack_base_mesh(const nlohmann::json& base_mesh);

/// The inverse (numbers rounded to float).
/// \throw InputError naming what is wrong: bytes that do
/// not inflate, an inflated size beyond what deflate can produce from them, not CBOR, or records
/// and corners that do not agree. base_mesh_from_json checks the mesh itself.
nlohmann::json unpack_base_mesh(const std::string& bytes);

}  // namespace sdm
