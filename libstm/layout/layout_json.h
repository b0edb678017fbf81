#pragma once
/// Layout files (JSON): {"format": "sdm-layout", "version": 1, "size", "margin", "scale", "coverage",
/// "coverage_inner", "assignment" (Layout::assignment; absent: 1), "skeleton": {...}, "segments":
/// [{"edge", "a", "b", "axis", "e1", "e2", "radius", "cap", "length", "area", "weight",
/// "rect": [x, y, w, h], "rotated", "d", "extend" ([at a, at b] in radii; only with assignment 3,
/// absent: none), "neighbours_a", "neighbours_b"}]}.
#include "libstm/core/input_file.h"
#include "libstm/layout/layout.h"

#include <nlohmann/json.hpp>
#include <string>

namespace sdm {

nlohmann::json layout_to_json(const Layout& layout);
/// Besides the structure, checks what compute_layout guarantees (atlas size within kMaxImageSide,
/// rectangles inside the atlas in 64-bit arithmetic, orthonormal frames, positive radii and
/// weights, the skeleton's checks of check_skeleton_geometry), so a crafted file cannot index out
/// of bounds.
/// \throw InputError naming what is wrong.
Layout layout_from_json(const nlohmann::json& j);
/// Written atomically (write_text_file, atomic_file.h).
/// \throw InputError when the target is not a regular file or its folder is missing;
/// std::runtime_error when the write fails.
void write_layout_json(const Layout& layout, const std::string& path);
/// Reads a layout written by write_layout_json; `budget` as for read_skeleton_json.
/// \throw InputError naming the file: not a regular file, too large, refused by `budget`, not JSON,
/// not a valid layout (layout_from_json).
Layout read_layout_json(const std::string& path, const ReadBudget& budget = {});

}  // namespace sdm
