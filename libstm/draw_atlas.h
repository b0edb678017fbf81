#pragma once
// A CPU picture of a layout: every rectangle (its margin dark, its inside light) with the
// segment's triangles drawn into it in the segment's colour, seam triangles on both sides.
// For looking at a layout; the real atlas rendering (textures, margins filled from the surface)
// runs on the GPU.
#include "libstm/layout.h"

#include <cstdint>
#include <string>
#include <vector>

namespace stm {

// RGBA, layout.size x layout.size, row 0 at the top (image order; atlas y = 0 is the bottom row).
std::vector<std::uint8_t> draw_atlas(const Mesh& mesh, const Layout& layout, const std::vector<int>& face_segment);

// draw_atlas written as PNG (atomically).
void write_atlas_png(const Mesh& mesh, const Layout& layout, const std::vector<int>& face_segment, const std::string& path);

}  // namespace stm
