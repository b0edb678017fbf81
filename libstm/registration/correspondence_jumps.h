#pragma once
/// Where a correspondence tears: target vertices whose source point jumps away from their
/// neighbours' (a speck of wrong colour in a transferred texture, a patch of the target that shows
/// another part of the source). Needs no known answer, so every transfer reports it.
#include "libstm/mesh/mesh.h"
#include "libstm/registration/carry_skeleton.h"

#include <vector>

namespace sdm {

struct CorrespondenceJumps {
  double area_share = 0;  ///< the jumping vertices' share of the target's area (a third of each face's area per corner)
  long vertices = 0;      ///< how many vertices jump
  int example = -1;       ///< the jumping vertex of the largest area, or -1
};

/// The target vertices whose source point (`assigned`, one per target vertex: a face of `source`
/// and barycentric coordinates) lies farther than `distance` (model units of the source) from the
/// source points of more than half of their neighbours along the target's edges. Throws
/// InputError when the counts differ or a face lies outside the source.
CorrespondenceJumps correspondence_jumps(const Mesh& source, const Mesh& target, const std::vector<SourcePoint>& assigned, double distance);

}  // namespace sdm
