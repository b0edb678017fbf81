#pragma once
// The SDM file: one OpenEXR image whose channels hold, per texel of the STM, the displacement of
// the surface along the texel's capsule ray (model units) and whether the texel holds surface of its
// own segment, plus optional vector channels. The layout JSON (skeleton, frames, rectangles)
// travels in the header, so a decoder needs nothing else.
//
// Format version 2 (issue 14) names the channels so that image tools show the map: the displacement
// is the luminance channel "Y" and the mask the alpha channel "A" (an RGBA reader, a thumbnailer or
// Blender shows a grey image of D where the surface is; version 1's "D" and "A" sort to "A, D" and
// showed black), the vector channels are the layer "vector.X/Y/Z". Version 1 files still read.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sdm {

constexpr int kSdmFormatVersion = 2;

struct SdmImage {
  int width = 0, height = 0;
  std::vector<float> D, A;             // width * height, rows top to bottom
  std::vector<float> X, Y, Z;          // optional vector mode (offsets in the segment frame), or empty
  nlohmann::json layout;               // the layout the texels refer to
};

enum class SdmPrecision { float32, half16 };

// Writes the displacement as channel Y and the mask as A (and vector.X/Y/Z when present), ZIP-
// compressed, with the layout in the string attribute "sdm_layout" and the version in
// "sdm_format_version". The displacement and vector channels in `precision` (half: 11 significant
// bits, about 3 decimal digits; the mask, 0 or 1, is always half). Atomic.
void write_sdm_exr(const SdmImage& image, const std::string& path, SdmPrecision precision = SdmPrecision::float32);

// Reads and checks an SDM file. Throws InputError that names the problem: missing file, not an
// OpenEXR file, truncated or unreadable pixels, missing channels, missing or invalid layout,
// unknown format version.
SdmImage read_sdm_exr(const std::string& path);

}  // namespace sdm
