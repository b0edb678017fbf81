#pragma once
/// The L2 stretch of a texture parameterization (Sander et al. 2001).
#include "libstm/mesh/mesh.h"

#include <vector>

namespace sdm {

/// Area-weighted L2 stretch of a mesh with per-halfedge texcoords, over the given faces (all when
/// empty), after scaling the texture domain so that the faces' parameter area equals their surface
/// area: sqrt(sum A_f (|dp/ds|^2 + |dp/dt|^2)/2 / sum A_f); 1 is ideal. Faces degenerate in the
/// texture domain are skipped; 0 when the faces have no area.
/// \pre every index in `faces` is a face of `mesh`.
/// \throw InputError when the mesh has no texture coordinates.
double l2_stretch(const Mesh& mesh, const std::vector<int>& faces = {});

}  // namespace sdm
