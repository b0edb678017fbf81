#pragma once
// Dropping specks (issue 15): a tiny separate part beside a model (a stray tetrahedron 1e-3 of its
// size) gets a rectangle too small for any texel of the atlas, so the layout refuses the whole
// model. `--min-part F` drops such parts before the pipeline runs, and says what it dropped.
#include "libstm/mesh/mesh.h"

#include <string>
#include <vector>

namespace sdm {

struct DroppedParts {
  Mesh mesh;                          // the parts kept (uv kept where the input had them)
  std::vector<std::string> dropped;   // one line per dropped part: faces, size and place
};

// Keeps the vertex-connected parts whose bounding-box diagonal is at least `fraction` of the whole
// mesh's, in their vertex and face order. Throws InputError when no part is that large (a
// fraction of 1 or more) or `fraction` is negative or not finite.
DroppedParts drop_small_parts(const Mesh& mesh, double fraction);

}  // namespace sdm
