#pragma once
/// Mesh files that keep the positions write_mesh was given. OpenMesh's OFF and PLY writers round
/// every coordinate to a 32-bit float (1000000.317288 became 1000000.3125 in text OFF), so OFF is
/// written here with each double's shortest round-trip digits, and binary PLY with double
/// coordinates whenever float would change one. STL and glTF hold float32 only: what rounding costs
/// there is measured (float32_rounding) so that callers can say so.
#include "libstm/mesh/mesh.h"

#include <string>

namespace sdm {

/// Text OFF: "OFF", the counts, one vertex a line (shortest digits that read back to the same
/// double), one triangle a line.
std::string off_text(const Mesh& mesh);

/// Binary little-endian PLY: x, y, z as float when every coordinate is a float already, else as
/// double; faces as a uchar-counted list of int.
std::string ply_bytes(const Mesh& mesh);

/// The largest distance a vertex moves when its coordinates are rounded to float32, as a fraction of
/// the bounding-box diagonal (0 for an empty or a point-sized mesh): what STL and glTF lose.
double float32_rounding(const Mesh& mesh);

/// Whether write_mesh rounds positions to float32 at the format `path`'s extension names (.stl,
/// .glb, .gltf).
bool writes_float32(const std::string& path);

}  // namespace sdm
