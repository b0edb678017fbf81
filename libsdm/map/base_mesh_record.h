#pragma once
/// The base mesh an SDM is rebuilt from, as the file holds it (base_mesh.h in libsdm/encode says how
/// the encoder makes it; DESIGN 4.8): triangles, the segment of each face and each corner's capsule
/// coordinates and displacement, never positions. Shared by the encoder, the decoder and the file.
#include <Eigen/Dense>
#include <array>
#include <nlohmann/json.hpp>
#include <vector>

namespace sdm {

struct BaseMesh {
  Eigen::MatrixX3i triangles;                           ///< consistently oriented, closed unless the input had holes
  std::vector<int> face_segment;                        ///< segment of each face
  std::vector<std::array<Eigen::Vector2d, 3>> corner_uv;  ///< (u, v) of each corner in its face's segment
  /// Displacement of each corner along its capsule ray (model units): with it the decoder places the
  /// base mesh's corners exactly instead of reading them from the map. Empty in maps of format 1-2.
  std::vector<std::array<double, 3>> corner_d;
  /// Position of each corner in the input mesh: known to the encoder only (not stored in the file;
  /// empty after base_mesh_from_json).
  std::vector<std::array<Eigen::Vector3d, 3>> corner_position;
  /// Faces whose points the decoder places on the flat triangle of their decoded corners, not on
  /// their rays: where the map cannot carry a face (its rays graze the surface, so neighbouring
  /// texels hold far apart depths) and the flat face lies closer (encode_sdm.cpp). Sorted; empty in
  /// maps of format 1-3.
  std::vector<int> flat_faces;
};

/// Whether base faces f and g (rows of `triangles`) share a corner, or are one face: the faces whose
/// texels a point of f may read (decode_sdm) and whose input f's texels may cross (base_regions.h).
bool faces_share_corner(const Eigen::MatrixX3i& triangles, int f, int g);

nlohmann::json base_mesh_to_json(const BaseMesh& base);
/// \throw InputError naming what is wrong (sizes, indices, segments out of range, non-finite texel
/// coordinates, degenerate faces, unused vertices, or a surface that is not manifold and consistently oriented).
BaseMesh base_mesh_from_json(const nlohmann::json& j, int segments);

}  // namespace sdm
