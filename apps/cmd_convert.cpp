#include "apps/cli_common.h"
#include "apps/commands.h"
#include "libstm/core/errors.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/validate_mesh.h"

#include <memory>

namespace sdm::cli {
namespace {

// Reads, repairs (unless --no-repair or --strict), validates and writes; returns what happened and,
// in `rounding`, what a float32 format's rounding cost (note_float32_rounding).
sdm::LoadReport convert(const std::string& in, const std::string& out, bool strict, double& rounding) {
  if (strict) input_settings().no_repair = true;
  sdm::LoadedMesh m = load_input(in);
  if (strict) check_strict(m.report.validation, in);
  for (const auto& f : m.report.validation.findings)
    progress("note: " + std::to_string(f.count) + " " + f.kind + ", e.g. " + f.example);
  sdm::write_mesh(m.mesh, out, m.texture);
  rounding = note_float32_rounding(m.mesh, out);
  progress("wrote " + out + " (" + std::to_string(m.mesh.n_vertices()) + " vertices, " + std::to_string(m.mesh.n_faces()) + " faces)");
  return std::move(m.report);
}

}  // namespace

Command add_convert_command(CLI::App& parent) {
  struct Opts {
    std::string mesh, out;
    bool strict = false, json = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "convert", "Write a mesh in another format (OBJ with uv and MTL, PLY, OFF, STL, glTF), repaired as every command\n"
                 "repairs it. Refuses (exit 2, nothing written) a mesh the pipeline cannot take.");
  app->add_option("mesh", o->mesh, "Input mesh (.obj, .off, .ply, .stl, .glb, .gltf)")->required();
  app->add_option("-o,--output", o->out, "Output mesh; the format follows the extension")->required();
  app->add_flag("--strict", o->strict,
                "Repair nothing, and also refuse meshes with tolerated findings (degenerate faces, isolated vertices, holes)");
  add_repair_options(app);
  app->add_flag("--json", o->json, "Print one JSON object: the output and what rounding to a float32 format (STL, glTF) cost");
  return {app, [o]() {
            double rounding = 0;
            convert(o->mesh, o->out, o->strict, rounding);
            if (o->json) print_json({{"input", o->mesh}, {"output", o->out}, {"float32_rounding", rounding}});
            return 0;
          }};
}

Command add_repair_command(CLI::App& parent) {
  struct Opts {
    std::string mesh, out;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "repair", "Repair a mesh as every command does before it works (welds coincident vertices, drops duplicated and\n"
                "collapsed faces, splits non-manifold edges and vertices, orients every part outward, drops isolated\n"
                "vertices) and write the result; each repair is named. Exit 2 when even the repaired mesh is refused.");
  app->add_option("mesh", o->mesh, "Input mesh (.obj, .off, .ply, .stl, .glb, .gltf)")->required();
  app->add_option("-o,--output", o->out, "Repaired mesh; the format follows the extension")->required();
  app->add_flag("--json", o->json, "Print one JSON object: the repairs and the repaired mesh's validation");
  add_weld_tolerance_option(app);
  return {app, [o]() {
            double rounding = 0;
            const sdm::LoadReport r = convert(o->mesh, o->out, false, rounding);
            if (!r.repair.changed()) progress("nothing to repair");
            if (o->json) {
              nlohmann::json j = {{"input", o->mesh}, {"output", o->out}, {"changed", r.repair.changed()},
                                  {"faces_dropped", r.repair.faces_dropped()}, {"validation", r.validation.to_json()},
                                  {"float32_rounding", rounding}};
              print_json(j);
            }
            return 0;
          }};
}

}  // namespace sdm::cli
