#pragma once
// What encode and roundtrip share: the layout they compute, the --precision help, and the quality
// gate of a map (the input's self-intersections, the share of the surface the decoded map carries,
// the encoder's check of its own faces).
#include "apps/cli_common.h"
#include "libsdm/encode/encode_sdm.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/self_intersections.h"
#include "libstm/mesh/surface_distance.h"

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <string>

namespace sdm::cli {

// The layout encode and roundtrip use: the stages announced, the atlas size given, the default margin.
LayoutSource encode_layout_source(const std::string& layout_file, const std::string& skeleton_file, int size);

constexpr const char* kPrecisionHelp =
    "Displacement precision in the file: float (32 bits), half (16 bits: 11 significant bits), or a number of bits "
    "from 4 to 11: the residual against the flat base mesh, quantised (the smallest file; docs/BENCHMARKS.md)";

// "(x, y, z)" for a message.
std::string point_text(const Eigen::Vector3d& p);

// The quality gate of encode and roundtrip. A surface that crosses itself has two sheets
// where a map holds one per ray (a Spot with its head pushed through its body encoded silently to
// 1.2 % RMS): named on stderr, refused under --strict.
sdm::SelfIntersections check_self_intersections(const sdm::Mesh& mesh, bool strict);

// The share of the input's surface (by vertex area) that the decoded surface carries within 1 % of
// the diagonal (diag: the input's). Under `floor` (--min-carried, 90 % by default): a warning, or a
// refusal under --strict.
constexpr double kCarriedTolerance = 0.01;
sdm::SurfaceCoverage check_carried(const sdm::Mesh& input, const sdm::Mesh& decoded, double diag, double floor, bool strict);

// The encoder's check of its own map (EncodeOptions::flat_above; refine_above three times it).
void add_face_error_option(CLI::App* app, double& error);
void encode_check_options(sdm::EncodeOptions& eo, double face_error);
// --min-carried: the floor of check_carried.
void add_min_carried_option(CLI::App* app, double& floor);

}  // namespace sdm::cli
