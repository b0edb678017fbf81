#include "apps/cli_common.h"

#include "apps/commands.h"
#include "apps/memory_budget.h"
#include "libstm/core/errors.h"
#include "libstm/core/stopwatch.h"
#include "libstm/layout/layout_json.h"
#include "libstm/mesh/fill_holes.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/write_positions.h"
#include "libstm/skeleton/extract_skeleton.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace sdm::cli {
namespace {

sdm::Layout read_layout_for(const sdm::Mesh& mesh, const LayoutSource& source, const std::string& max_memory) {
  const std::string& path = source.layout_file;
  sdm::Layout layout = source.read ? *source.read : sdm::read_layout_json(path, json_budget(max_memory, path));
  if (layout.skeleton.vertex_node.size() != mesh.n_vertices())
    throw sdm::InputError("layout " + path + " was made for a mesh with " + std::to_string(layout.skeleton.vertex_node.size()) +
                          " vertices, this one has " + std::to_string(mesh.n_vertices()));
  return layout;
}

}  // namespace

LayoutForMesh layout_for(const sdm::Mesh& mesh, const LayoutSource& source, const std::string& max_memory) {
  LayoutForMesh r;
  if (!source.layout_file.empty()) {
    r.layout = read_layout_for(mesh, source, max_memory);
    return r;
  }
  const sdm::Progress stage_progress =
      source.announce_stages ? sdm::Progress([](const std::string& s) { progress("  " + s); }) : sdm::Progress(progress);
  sdm::Stopwatch clock;
  sdm::Skeleton skeleton;
  if (!source.skeleton_file.empty()) {
    skeleton = sdm::read_skeleton_json(source.skeleton_file, json_budget(max_memory, source.skeleton_file));
  } else {
    if (source.announce_stages) progress("extracting the skeleton");
    skeleton = sdm::extract_skeleton(mesh, {}, stage_progress);
  }
  r.skeleton_seconds = clock.lap();
  sdm::LayoutOptions options = source.options;
  options.progress = stage_progress;
  if (source.announce_stages) progress("computing the layout");
  r.layout = sdm::compute_layout(mesh, skeleton, options);
  r.layout_seconds = clock.lap();
  r.computed = true;
  return r;
}

InputSettings& input_settings() {
  static InputSettings settings;
  return settings;
}

sdm::LoadOptions load_options(double min_part) {
  sdm::LoadOptions options;
  options.min_part = min_part;
  options.repair = !input_settings().no_repair;
  options.repair_options.weld_tolerance = input_settings().weld_tolerance;
  return options;
}

void add_weld_tolerance_option(CLI::App* app) {
  app->add_option("--weld-tolerance", input_settings().weld_tolerance,
                  "Weld boundary vertices closer than this fraction of the bounding-box diagonal (0: exact duplicates only)")
      ->capture_default_str()
      ->check(number_in(0.0, 0.01));
}

void add_repair_options(CLI::App* app) {
  app->add_flag("--no-repair", input_settings().no_repair,
                "Refuse a mesh with defects instead of repairing it (coincident vertices, duplicated faces, non-manifold\n"
                "edges and vertices, inconsistent orientation: by default each is repaired and named on stderr)");
  add_weld_tolerance_option(app);
}

namespace {
nlohmann::json& repairs_seen() {
  static nlohmann::json seen = nlohmann::json::array();
  return seen;
}
}  // namespace

sdm::LoadedMesh load_input(const std::string& path, double min_part, bool fill) {
  // Specks are dropped before validation: one it would refuse (a stray flat triangle) does not stop the model.
  sdm::LoadedMesh m = sdm::load_mesh(path, load_options(min_part));
  for (const auto& d : m.report.dropped) progress("--min-part: dropped " + d);
  for (const auto& line : sdm::repair_lines(m.report.repair)) progress(path + ": " + line);
  if (m.report.repair.changed()) {
    nlohmann::json j = m.report.repair.to_json();
    j["file"] = path;
    repairs_seen().push_back(j);
  }
  if (!fill) return m;
  const size_t before = m.mesh.n_vertices();
  const int loops = int(sdm::boundary_loops(sdm::face_matrix(m.mesh), int(before)).size());
  if (loops == 0) return m;
  m.mesh = sdm::fill_holes(m.mesh);
  m.colors.clear();
  progress("--fill-holes: closed " + std::to_string(loops) + " hole(s) with " + std::to_string(m.mesh.n_vertices() - before) + " vertices");
  return m;
}

Mesh load_mesh_min_part(const std::string& path, double min_part, bool fill) { return load_input(path, min_part, fill).mesh; }

void print_json(nlohmann::json j) {
  if (j.is_object() && !repairs_seen().empty()) j["repair"] = repairs_seen();
  // A path that is not UTF-8 (a file name in Latin-1) is printed with U+FFFD where its bytes are not
  // text; the strict dump threw after the command's work, and the run failed with its outputs removed.
  std::cout << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << std::endl;
}

void add_fill_holes_option(CLI::App* app, bool& value) {
  app->add_flag("--fill-holes", value,
                "Close an open mesh's holes first (smooth patches), so that the output is closed; by default the output\n"
                "keeps the holes open");
}

void add_min_part_option(CLI::App* app, double& value) {
  app->add_option("--min-part", value,
                  "Drop separate parts smaller than this fraction of the model's bounding-box diagonal (specks\n"
                  "too small for any texel), naming each")
      ->check(number_in(0.0, 1.0));
}

double note_float32_rounding(const Mesh& mesh, const std::string& path) {
  if (!sdm::writes_float32(path)) return 0;
  const double rounding = sdm::float32_rounding(mesh);
  if (rounding > kFloat32Warning) {
    char line[160];
    std::snprintf(line, sizeof line, "%.2g of the bounding-box diagonal", rounding);
    progress("warning: " + path + " holds 32-bit floats: rounding moved vertices by up to " + line +
             " (the model lies far from the origin for its size); write .obj, .off or .ply to keep every digit");
  }
  return rounding;
}

namespace {

// A bound as %g writes it, its exponent without sign or leading zeros (1e+06 reads as 1e6).
std::string bound_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  std::string s = buf;
  const size_t e = s.find('e');
  if (e == std::string::npos) return s;
  std::string exponent = s.substr(e + 1);
  const bool negative = exponent[0] == '-';
  exponent = exponent.substr(exponent.find_first_not_of("+-0"));
  return s.substr(0, e) + "e" + (negative ? "-" : "") + exponent;
}

CLI::Validator number_check(double lo, double hi, bool open_low) {
  const std::string range = std::string(open_low ? "(" : "[") + bound_text(lo) + ", " + bound_text(hi) + "]";
  return CLI::Validator(
      [lo, hi, open_low, range](std::string& input) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(input.c_str(), &end);
        if (input.empty() || end != input.c_str() + input.size())
          return "'" + input + "' is not a number; give one in " + range;
        const bool inside = std::isfinite(x) && (open_low ? x > lo : x >= lo) && x <= hi;
        if (!inside) return input + " is out of range; give a finite number in " + range;
        return std::string();
      },
      "in " + range);
}

}  // namespace

CLI::Validator number_in(double lo, double hi) { return number_check(lo, hi, false); }
CLI::Validator number_above(double lo, double hi) { return number_check(lo, hi, true); }

}  // namespace sdm::cli
