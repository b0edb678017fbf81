#pragma once
// The limits every reader and command enforces, in one place, so that a companion file (layout,
// skeleton, SDM header) cannot ask for more than the command line would accept (DESIGN 6).
#include <cfloat>

namespace sdm {

// Largest atlas, SDM image or rendered image side in texels/pixels (--size, --width, --height).
constexpr int kMaxImageSide = 16384;

// Largest coordinate magnitude accepted in a mesh or skeleton: mesh readers parse single
// precision, so a coordinate beyond the float range cannot be represented faithfully.
constexpr double kMaxCoordinate = double(FLT_MAX);

}  // namespace sdm
