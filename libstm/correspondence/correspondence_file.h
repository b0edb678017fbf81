#pragma once
/// The correspondence as a file (`sdm correspond`, `sdm transfer --correspondence`): per target vertex,
/// in order, the source face and the barycentric coordinates of the source point it shows.
#include "libstm/registration/carry_skeleton.h"

#include <string>
#include <vector>

namespace sdm {

/// As text (a comment, then one line per target vertex: face w0 w1 w2) or, with `json`, one JSON
/// object {"target_vertices", "source_face": [...], "barycentric": [[w0, w1, w2], ...]}.
std::string correspondence_text(const std::vector<SourcePoint>& points, bool json);

}  // namespace sdm
