#pragma once
/// A CPU picture of a layout: every rectangle (its margin dark, its inside light) with the
/// segment's triangles drawn into it in the segment's colour, seam triangles on both sides.
/// For looking at a layout; the real atlas rendering (textures, margins filled from the surface)
/// runs on the GPU.
#include "libstm/core/image.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"

#include <cstdint>
#include <string>
#include <vector>

namespace sdm {

/// RGBA, layout.size x layout.size, row 0 at the top (image order; atlas y = 0 is the bottom row).
std::vector<std::uint8_t> draw_atlas(const Mesh& mesh, const Layout& layout, const std::vector<int>& face_segment);

/// draw_atlas written as PNG (atomically).
void write_atlas_png(const Mesh& mesh, const Layout& layout, const std::vector<int>& face_segment, const std::string& path);

/// A checkerboard atlas for looking at the parameterization (sdm render --checker): squares of
/// `square` texels in every rectangle, aligned with its local (u, v) so they follow each capsule's
/// axis, light and dark shades of the segment's colour; margins repeat the pattern, outside is grey.
/// RGBA, rows top to bottom (atlas y = 0 at the bottom), layout.size^2.
Image checker_atlas(const Layout& layout, int square = 16);

}  // namespace sdm
