#pragma once
/// The control mesh an SDM is rebuilt from: a coarse copy of the input's topology whose corners are
/// stored only as capsule coordinates (segment, u, v), never as positions. Positions come from the
/// skeleton and the displacement map at decode time, so a moved skeleton moves the surface.
///
/// Why not one capsule control mesh per segment (DECISIONS 4, "SDM decode"): segment regions meet
/// along irregular curves around branch nodes, and independent capsule patches cannot be stitched
/// into one closed manifold there. A decimated copy of the input is manifold by construction, with
/// the input's boundary loops where it has holes, and its faces carry their segment, so levels of
/// detail stay per segment.
#include "libstm/core/progress.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"
#include "libsdm/map/base_mesh_record.h"

#include <memory>

namespace sdm {

/// Decimates `mesh` (quadric error, halfedge collapses that keep topology and original vertex
/// positions) to about `target_vertices`, assigns faces to segments (segments.h) and maps each
/// corner into its face's capsule. A map texel holds one depth per ray, so a face its segment cannot
/// carry alone (turned away from the segment's rays, wrapped around its axis, or folded over by
/// another sheet of the same segment's faces along those rays) moves to the nearest segment that
/// can. target_vertices <= 0 picks a size from the mesh. `progress` hears of the decimation's rounds
/// on large meshes (vertices, seconds, an estimate of the rest). `surface`, when given, is a BVH of
/// `mesh` (vertex_matrix, face_matrix) that the remesh of a large or needle mesh projects onto (the
/// encoder's own, so that none is built twice).
BaseMesh make_base_mesh(const Mesh& mesh, const Layout& layout, int target_vertices = 0, const Progress& progress = {},
                        const TriangleBvh* surface = nullptr);

/// What make_base_mesh decimates, kept so that the encoder can decimate it again with some of its
/// vertices kept where the first base mesh could not carry the surface (encode_sdm.cpp): the input
/// and its skeleton nodes, or an isotropic remesh of it for large and needle meshes.
class BaseMeshSource {
 public:
  BaseMeshSource(const Mesh& mesh, const Layout& layout, int target_vertices = 0, const TriangleBvh* surface = nullptr);
  ~BaseMeshSource();
  BaseMeshSource(BaseMeshSource&&) noexcept;

  /// The vertices a base mesh is decimated from (rows: the source's vertex indices).
  Eigen::MatrixX3d points() const;
  /// The base mesh, with every vertex v where keep[v] != 0 (keep empty, or one entry per row of
  /// points()) kept: the target grows by their number, so the rest is decimated as before.
  BaseMesh decimate(const std::vector<char>& keep = {}, const Progress& progress = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sdm
