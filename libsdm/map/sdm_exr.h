#pragma once
/// The SDM file: one OpenEXR image whose channels hold, per texel of the STM, the displacement of
/// the surface along the texel's capsule ray (model units) and whether the texel holds surface of its
/// own segment, plus optional vector channels. The layout JSON (skeleton, frames, rectangles)
/// travels in the header, so a decoder needs nothing else.
///
/// Format version 2 names the channels so that image tools show the map: the displacement
/// is the luminance channel "Y" and the mask the alpha channel "A" (an RGBA reader, a thumbnailer or
/// Blender shows a grey image of D where the surface is; version 1's "D" and "A" sort to "A, D" and
/// showed black), the vector channels are the layer "vector.X/Y/Z". Version 1 files still read.
///
/// Format version 3 (compact maps) keeps the channels and adds: the base mesh in binary
/// (attribute "sdm_base_mesh": CBOR, deflated, with the displacement of every corner, so the decoder
/// places corners exactly); texels no base face reads written as 0 (D and A), so compression removes
/// them; and a quantised precision: Y holds the displacement's residual against the decoder's own
/// prediction (the point of the flat base face, projected on the texel's ray), rounded to a step q,
/// as (k + 2^(b-1)) / 2^b for an integer k of b bits (exact in half: a grey image in (0, 1), 0.5
/// where the surface is the flat base face). Versions 1 and 2 still read.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sdm {

/// Format version 4 adds the base mesh's flat faces (base_mesh.h), which a reader of
/// version 3 would decode on their rays; a map without them is still written as version 3.
constexpr int kSdmFormatVersion = 4;

struct SdmImage {
  int width = 0, height = 0;
  std::vector<float> D, A;             ///< width * height, rows top to bottom
  std::vector<float> X, Y, Z;          ///< optional vector mode (offsets in the segment frame), or empty
  nlohmann::json layout;               ///< the layout the texels refer to (with "base_mesh")
  /// From the encoder: per texel, the decoder's prediction of D (the flat base face's point
  /// projected on the texel's ray), NaN where no base face reads the texel. Empty when read.
  std::vector<float> foot;
  /// From a quantised file: D holds the residual against that prediction, not the displacement.
  bool residual = false;
};

/// How the displacement is stored: float (32 bits), half (16 bits: 11 significant bits), or the
/// residual against the decoder's prediction quantised to `bits` (4..11; the step is the largest
/// residual over 2^(bits-1) - 1).
struct SdmPrecision {
  enum Kind { float32, half16, quantized };
  Kind kind = float32;
  int bits = 0;
  SdmPrecision(Kind k = float32, int b = 0) : kind(k), bits(b) {}
  /// "float", "half" or a number of bits 4..11; throws InputError naming the choices.
  static SdmPrecision parse(const std::string& text);
  std::string name() const;
};

/// Writes format version 4 when the base mesh has flat faces, else 3: the displacement as channel Y
/// and the mask as A (and vector.X/Y/Z when present, float or half only), compressed (ZIP), the
/// layout in the string attribute "sdm_layout" (its skeleton's vertex_node left empty: it describes
/// the input mesh, not the map's), the base mesh in "sdm_base_mesh" and the version in
/// "sdm_format_version". Texels whose foot is NaN are written as 0. The mask, 0 or 1, is always
/// half. Written atomically (write_atomically).
/// \pre a quantised precision has `foot` (one per texel), 4 to 11 bits and no vector channels.
/// \throw std::invalid_argument when the channels do not match the image's size or the
/// precondition fails; InputError when the target is not a regular file or its folder is missing.
void write_sdm_exr(const SdmImage& image, const std::string& path, SdmPrecision precision = SdmPrecision::float32);

/// The image as a reader of a file written with `precision` sees it (no file): D rounded to half,
/// or replaced by the quantised residual. For the encoder's own check of what it writes.
SdmImage as_stored(SdmImage image, SdmPrecision precision);

/// Reads and checks an SDM file.
/// \throw InputError that names the problem: missing file, not an
/// OpenEXR file, truncated or unreadable pixels, missing channels, missing or invalid layout,
/// unknown format version.
SdmImage read_sdm_exr(const std::string& path);

}  // namespace sdm
