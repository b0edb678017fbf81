#pragma once
/// Making a layout (DESIGN 4.3-4.7): long edges cut, segments, face assignment, frames, rectangle
/// sizes and packing.
#include "libstm/core/progress.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/skeleton.h"

#include <vector>

namespace sdm {

struct LayoutOptions {
  int size = 1024;
  int margin = 4;
  std::vector<double> weights;  ///< per edge of the input skeleton (its pieces share it), empty: all 1
  /// Edges longer than split_ratio times their radius are cut into pieces first
  /// (split_segments.h); 0 keeps the skeleton's edges as they are.
  double split_ratio = 2.0;
  /// Rectangles grow into leftover space up to this ratio between their two growth factors
  /// (pack_rectangles.h); 1 keeps the uniform texel density exactly.
  double max_anisotropy = 1.25;
  Progress progress;
};

/// Long edges cut (options.split_ratio; the layout keeps the cut skeleton), then segments, face
/// assignment, frames, rectangle sizes (w = L + (extensions) r + 2d, h = 2 pi r, times the weight)
/// and packing.
/// \pre `skeleton`'s vertex map is `mesh`'s.
/// \throw InputError for a skeleton that does not fit the mesh, weights that are not one positive
/// number per skeleton edge, or an atlas too small for the rectangles (naming the --size that holds them).
Layout compute_layout(const Mesh& mesh, const Skeleton& skeleton, const LayoutOptions& options = {});

}  // namespace sdm
