#pragma once
/// Skeleton displacement map decoding (paper 5, DESIGN 4.8): the base mesh in the SDM header is
/// tessellated with OpenSubdiv's Bfr patterns at a rate of 2^level per face (the level of its
/// segment), each new point is placed on its capsule ray at the displacement read from the map, and
/// the result is one closed mesh whatever the mix of levels (tessellate_mesh.h).
#include "libsdm/decode/untangle_decoded.h"
#include "libsdm/map/sdm_exr.h"
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/posed_skeleton.h"

#include <map>
#include <optional>

namespace sdm {

struct DecodeOptions {
  int level = 3;                       ///< level of detail: each base edge is cut into 2^level pieces
  std::map<int, int> segment_level;    ///< per-segment overrides
  /// A pose: the map's skeleton with moved nodes (same graph), optionally node_rotations and
  /// segment_radius_scale. The surface is decoded at rest, then deformed (libsdm/pose/deform_decoded.h).
  std::optional<PosedSkeleton> skeleton;
};

/// Where each output vertex comes from: the segment that placed it and its base face; and the base
/// face of each output face; the folds untangled (untangle_decoded.h).
struct DecodeTrace {
  std::vector<int> vertex_segment, vertex_base_face, face_base_face;
  UntangleReport untangle;
};

/// \throw InputError when the header lacks a layout or base mesh, a level is out of range (0..8),
/// a segment id is unknown, or the skeleton's graph differs from the encoded one. `trace`, when
/// given, receives where each output vertex comes from.
Mesh decode_sdm(const SdmImage& image, const DecodeOptions& options = {}, DecodeTrace* trace = nullptr);

/// What decode_sdm places, without building the mesh: the points and triangles of the base faces
/// `faces` (every face when empty; the points on the chosen faces' borders are placed by them), each
/// point's and triangle's base face and each point's segment. For the encoder's check of its map
/// (encode_sdm.cpp), which decodes some faces again after choosing how to place them.
struct DecodedSurface {
  std::vector<Eigen::Vector3d> points;
  Eigen::MatrixX3i triangles;
  std::vector<int> point_face, triangle_face, point_segment;
  UntangleReport untangle;  ///< the folds untangled at rest (untangle_decoded.h)
};
DecodedSurface decode_surface(const SdmImage& image, const DecodeOptions& options = {}, const std::vector<int>& faces = {});
/// The surface's points as rows (for the queries that take a vertex matrix: surface_coverage, TriangleBvh).
Eigen::MatrixX3d point_matrix(const DecodedSurface& surface);

/// What decode_sdm makes with these options, before it runs: the triangles (4^L per base face of a
/// segment at level L) and the peak memory of decoding them and writing the result, at 450 bytes a
/// triangle (the halfedge mesh, the tessellation and the output's check; docs/BENCHMARKS.md).
/// \throw what decode_sdm throws for the header and levels.
struct DecodeEstimate {
  double triangles = 0;
  double bytes = 0;
};
DecodeEstimate estimate_decode(const SdmImage& image, const DecodeOptions& options = {});

}  // namespace sdm
