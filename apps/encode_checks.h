#pragma once
// What encode and roundtrip share: the --precision help, and the quality
// gate of a map (the input's self-intersections, the share of the surface the decoded map carries,
// the encoder's check of its own faces).
#include "apps/cli_common.h"
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_sdm.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/self_intersections.h"
#include "libstm/mesh/surface_distance.h"

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <string>

namespace sdm::cli {

constexpr const char* kPrecisionHelp =
    "Displacement precision in the file: float (32 bits), half (16 bits: 11 significant bits), or a number of bits "
    "from 4 to 11: the residual against the flat base mesh, quantised (the smallest file; docs/BENCHMARKS.md)";

// "(x, y, z)" for a message.
std::string point_text(const Eigen::Vector3d& p);

// The quality gate of encode and roundtrip. A surface that crosses itself has two sheets
// where a map holds one per ray (a head pushed through its body encodes silently to a poor RMS;
// docs/BENCHMARKS.md, "Thresholds: what they rest on"): named on stderr, refused under --strict.
sdm::SelfIntersections check_self_intersections(const sdm::Mesh& mesh, bool strict);

// The share of the input's surface (by vertex area) that the decoded surface carries within 1 % of
// the diagonal (diag: the input's). Under `floor` (--min-carried, 90 % by default): a warning, or a
// refusal under --strict.
constexpr double kCarriedTolerance = 0.01;
sdm::SurfaceCoverage check_carried(const sdm::Mesh& input, const sdm::Mesh& decoded, double diag, double floor, bool strict);
// The same against the decoder's points and triangles (decode_surface: what decode_sdm's mesh is
// made of, without its halfedge connectivity, which the check does not read).
sdm::SurfaceCoverage check_carried(const sdm::Mesh& input, const sdm::DecodedSurface& decoded, double diag, double floor, bool strict);

// The encoder's check of its own map (EncodeOptions::flat_above; refine_above three times it).
void add_face_error_option(CLI::App* app, double& error);
void encode_check_options(sdm::EncodeOptions& eo, double face_error);
// --min-carried: the floor of check_carried.
void add_min_carried_option(CLI::App* app, double& floor);

// The input and quality options encode and roundtrip share, in the order --help lists them.
struct EncodeQuality {
  double min_part = 0;                                       // --min-part
  bool fill_holes = false;                                   // --fill-holes
  std::string max_memory;                                    // --max-memory
  bool strict = false;                                       // --strict
  double min_carried = 0.9;                                  // --min-carried
  double face_error = sdm::EncodeOptions().flat_above;       // --face-error
};
// Adds --min-part, --no-repair and --weld-tolerance, --fill-holes, --max-memory, --strict (with
// `strict_help`, which says what the command refuses), --min-carried and --face-error, bound to `q`.
void add_encode_quality_options(CLI::App* app, EncodeQuality& q, const std::string& strict_help);

}  // namespace sdm::cli
