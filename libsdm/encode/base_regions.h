#pragma once
/// Which base faces an input face may be encoded for. Every input vertex belongs to the base face
/// whose flat triangle is nearest it (the base mesh's corners lie on the input, so its flat faces
/// follow the surface they stand for). A crossing of a base face's texel ray belongs to that face only
/// when the crossed input face has a corner belonging to it or to a base face that shares a corner
/// with it. On a CAD part's thin plate a ray that misses its face's own sheet meets the plate's other
/// side within reach of the flat point; that side's vertices belong to the base faces of the other
/// side, and the crossing is not taken. An input face longer than the base face (a CAD cylinder's
/// needle, 3 long and 2e-3 wide, whose base mesh comes from a remesh) has its corners far from the
/// crossing whatever side it is on: it is not judged, and always counts.
#include "libsdm/encode/base_mesh.h"

#include <Eigen/Dense>
#include <vector>

namespace sdm {

class BaseRegions {
 public:
  BaseRegions() = default;
  /// V, F: the input; base: its base mesh (corner_position filled: the encoder's).
  BaseRegions(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const BaseMesh& base);

  /// Whether input face `face` (a row of F) has a corner that belongs to base face `base_face` or
  /// to a base face sharing a corner with it, or is longer than the base face. True for every face
  /// when default-constructed.
  bool plausible(int face, int base_face) const;

  /// The base face input vertex v belongs to.
  int owner(int v) const { return owner_[size_t(v)]; }

 private:
  std::vector<int> owner_;                        ///< per input vertex, a base face
  std::vector<double> face_length_, base_length_;  ///< longest edge of each input face, base face
  Eigen::MatrixX3i F_, base_;
};

}  // namespace sdm
