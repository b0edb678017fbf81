#pragma once
/// A mesh's STM texture coordinates (DESIGN 3): its faces as atlas_triangles places them, per
/// halfedge, in [0, 1].
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"

#include <vector>

namespace sdm {

struct StmCoordinates {
  Mesh mesh;                      ///< copy of the input with per-halfedge STM texcoords in [0, 1]
  std::vector<int> face_segment;  ///< assign_faces(mesh, layout), or the one given
  int seam_faces = 0;             ///< faces unwrapped across phi = 0
  double coverage = 0;            ///< layout.coverage
  double stretch = 0;             ///< l2_stretch of the result
};

/// `face_segment`, when it has one entry per face, is used instead of assign_faces (a transfer
/// target takes the source's assignment through its correspondence, so both sides of a segment
/// border agree).
/// \throw InputError when a face names no segment of the layout.
StmCoordinates stm_coordinates(const Mesh& mesh, const Layout& layout, const std::vector<int>& face_segment = {});

}  // namespace sdm
