#pragma once
// The SDM file: one float OpenEXR image whose channels hold, per texel of the STM, the
// displacement of the surface along the texel's capsule ray (D, model units) and whether the texel
// holds surface of its own segment (A), plus optional vector channels. The layout JSON (skeleton,
// frames, rectangles) travels in the header, so a decoder needs nothing else.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sdm {

constexpr int kSdmFormatVersion = 1;

struct SdmImage {
  int width = 0, height = 0;
  std::vector<float> D, A;             // width * height, rows top to bottom
  std::vector<float> X, Y, Z;          // optional vector mode (offsets in the segment frame), or empty
  nlohmann::json layout;               // the layout the texels refer to
};

// Writes float32 channels D and A (and X, Y, Z when present), ZIP-compressed, with the layout in
// the string attribute "sdm_layout" and the version in "sdm_format_version". Atomic.
void write_sdm_exr(const SdmImage& image, const std::string& path);

// Reads and checks an SDM file. Throws InputError that names the problem: missing file, not an
// OpenEXR file, truncated or unreadable pixels, missing channels, missing or invalid layout,
// unknown format version.
SdmImage read_sdm_exr(const std::string& path);

}  // namespace sdm
