#pragma once
// What several subcommands share beyond commands.h: obtaining the layout of a mesh.
#include "libstm/layout/compute_layout.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace sdm::cli {

/// Where a command's layout comes from: the layout file when one is named, else a layout computed
/// around the skeleton file when one is named, else around a skeleton extracted here (the
/// default options of `sdm skeleton`).
struct LayoutSource {
  std::string layout_file;    // --layout
  std::string skeleton_file;  // --skeleton
  LayoutOptions options;      // of a computed layout (size, margin, ...); its progress is set by layout_for
  // Print a line as each stage starts ("extracting the skeleton", "computing the layout") with
  // the stage's own progress lines indented under it; otherwise the stage's lines only, as they are.
  bool announce_stages = false;
  // The layout file as check_layout_memory read it (within the memory budget), which layout_for
  // then serves: the file is parsed once. Empty until then, or without a layout file.
  std::optional<Layout> read;
};

struct LayoutForMesh {
  Layout layout;
  bool computed = false;         // false: read from the layout file
  double skeleton_seconds = 0;   // reading or extracting the skeleton (0 for a layout file)
  double layout_seconds = 0;     // computing the layout (0 for a layout file)
};

/// The layout of `mesh` from `source`, progress lines on stderr; a layout or skeleton file is read
/// within `max_memory` (--max-memory; json_budget), the layout file only where check_layout_memory
/// did not read it already (LayoutSource::read). Throws InputError when the layout file was made
/// for a mesh with another vertex count or is beyond the budget, and whatever reading the files,
/// extracting the skeleton or computing the layout throws.
LayoutForMesh layout_for(const Mesh& mesh, const LayoutSource& source, const std::string& max_memory);

/// How this run reads its meshes: repair on or off (--no-repair) and its weld tolerance, shared by
/// every input of the command (add_repair_options binds them).
struct InputSettings {
  bool no_repair = false;
  double weld_tolerance = sdm::kDefaultWeldTolerance;
};
InputSettings& input_settings();
/// The load options of this run's InputSettings (repair on or off, the weld tolerance), `min_part` set.
sdm::LoadOptions load_options(double min_part = 0);
/// Adds --weld-tolerance (bound to the InputSettings) to a command.
void add_weld_tolerance_option(CLI::App* app);
/// Adds --no-repair and --weld-tolerance to a command that reads meshes.
void add_repair_options(CLI::App* app);

/// Every command's mesh input: load_mesh with the run's InputSettings and `min_part` (the parts
/// smaller than that dropped before validation), saying on stderr what it dropped and repaired
/// (recorded for print_json), then, with fill, every hole closed (fill_holes), saying how many.
sdm::LoadedMesh load_input(const std::string& path, double min_part = 0, bool fill = false);
/// load_input's mesh alone.
Mesh load_mesh_min_part(const std::string& path, double min_part = 0, bool fill = false);
// Adds --fill-holes to a command: an open mesh's holes closed first, so that the output is closed
// (by default an open mesh stays open: the skeleton sees the holes filled, the output keeps them).
void add_fill_holes_option(CLI::App* app, bool& value);
// Adds --min-part to a command (encode, stm, roundtrip: the commands that compute a layout).
void add_min_part_option(CLI::App* app, double& value);

// After `mesh` was written to `path`: the largest move rounding to float32 made there, as a fraction
// of the diagonal (0 where the format keeps doubles: OBJ, OFF, PLY), with a warning on stderr
// naming the format when it exceeds kFloat32Warning (STL and glTF hold float32 only).
constexpr double kFloat32Warning = 1e-6;
double note_float32_rounding(const Mesh& mesh, const std::string& path);

// The check of every numeric option (`->check(number_in(lo, hi))`): a finite number from lo to hi,
// both included; number_above excludes lo. CLI11 runs it on the text before converting it, so nan,
// inf, -inf and values outside the range are refused (exit 2) with a message that names the option,
// the value and the range; --help shows the range after the type ("FLOAT:in [0, 1]").
CLI::Validator number_in(double lo, double hi);
CLI::Validator number_above(double lo, double hi);

}  // namespace sdm::cli
