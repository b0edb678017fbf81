#pragma once
/// Dropping specks: a tiny separate part beside a model (a stray tetrahedron 1e-3 of its
/// size) gets a rectangle too small for any texel of the atlas, so the layout refuses the whole
/// model. `--min-part F` drops such parts as the file is loaded, and says what it dropped.
#include "libstm/mesh/mesh.h"

#include <string>
#include <vector>

namespace sdm {

/// Drops the vertex-connected parts whose bounding-box diagonal is under `fraction` of the diagonal
/// of all the faces' box, before the soup is validated (load_mesh's min_part): their triangles and
/// uv are removed, their points left unused (build_mesh leaves them out), so that a speck validation
/// would refuse (a stray flat triangle of a scan) no longer stops the model. Triangles
/// with indices out of range, and parts with non-finite coordinates, stay for validation to name.
/// Returns one line per dropped part (faces, size and place).
/// \throw InputError when no part is
/// that large (a fraction of 1 or more) or `fraction` is negative or not finite. `kept_faces`, when
/// given and a part is dropped, receives the input number of every face kept, in order.
std::vector<std::string> drop_small_soup_parts(MeshSoup& soup, double fraction, std::vector<int>* kept_faces = nullptr);

}  // namespace sdm
