#pragma once
// The control mesh an SDM is rebuilt from: a coarse copy of the input's topology whose corners are
// stored only as capsule coordinates (segment, u, v), never as positions. Positions come from the
// skeleton and the displacement map at decode time, so a moved skeleton moves the surface.
//
// Why not one capsule control mesh per segment (DESIGN 4.8 first draft): segment regions meet
// along irregular curves around branch nodes, and independent capsule patches cannot be stitched
// into one closed manifold there. A decimated copy of the input is manifold by construction, with
// the input's boundary loops where it has holes, and its faces carry their segment, so levels of
// detail stay per segment.
#include "libstm/core/progress.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/layout/layout.h"

#include <array>
#include <nlohmann/json.hpp>

namespace sdm {

struct BaseMesh {
  Eigen::MatrixX3i triangles;                           // consistently oriented, closed unless the input had holes
  std::vector<int> face_segment;                        // segment of each face
  std::vector<std::array<Eigen::Vector2d, 3>> corner_uv;  // (u, v) of each corner in its face's segment
  // Displacement of each corner along its capsule ray (model units): with it the decoder places the
  // base mesh's corners exactly instead of reading them from the map. Empty in maps of format 1-2.
  std::vector<std::array<double, 3>> corner_d;
  // Position of each corner in the input mesh: known to the encoder only (not stored in the file;
  // empty after base_mesh_from_json).
  std::vector<std::array<Eigen::Vector3d, 3>> corner_position;
};

// Decimates `mesh` (quadric error, halfedge collapses that keep topology and original vertex
// positions) to about `target_vertices`, assigns faces to segments (segments.h) and maps each
// corner into its face's capsule. A map texel holds one depth per ray, so a face its segment cannot
// carry alone (turned away from the segment's rays, wrapped around its axis, or folded over by
// another sheet of the same segment's faces along those rays) moves to the nearest segment that
// can. target_vertices <= 0 picks a size from the mesh. `progress` hears of the decimation's rounds
// on large meshes (vertices, seconds, an estimate of the rest). `surface`, when given, is a BVH of
// `mesh` (vertex_matrix, face_matrix) that the remesh of a large or needle mesh projects onto (the
// encoder's own: building another cost 0.35 s at 450k vertices).
BaseMesh make_base_mesh(const Mesh& mesh, const Layout& layout, int target_vertices = 0, const Progress& progress = {},
                        const TriangleBvh* surface = nullptr);

/// Whether base faces f and g (rows of `triangles`) share a corner, or are one face: the faces whose
/// texels a point of f may read (decode_sdm) and whose input f's texels may cross (base_regions.h).
bool faces_share_corner(const Eigen::MatrixX3i& triangles, int f, int g);

nlohmann::json base_mesh_to_json(const BaseMesh& base);
// Throws InputError naming what is wrong (sizes, indices, segments out of range, non-finite texel
// coordinates, degenerate faces, unused vertices, or a surface that is not manifold and consistently oriented).
BaseMesh base_mesh_from_json(const nlohmann::json& j, int segments);

}  // namespace sdm
