// sdm repair: a mesh repaired as every command repairs it, each repair named.
#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/convert_mesh.h"
#include "libstm/mesh/load_mesh.h"

#include <memory>

namespace sdm::cli {
namespace {

// Repair's summary (its --json object) as text, on stderr as its progress.
void print_repair_text(const nlohmann::json& j) {
  print_written(j);
  if (!j["changed"].get<bool>()) progress("nothing to repair");
}

}  // namespace

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
            const Converted c = convert(o->mesh, o->out, false);
            const sdm::LoadReport& r = c.report;
            // One summary: --json prints it, the text reads it.
            const nlohmann::json j = {{"input", o->mesh}, {"output", o->out}, {"changed", r.repair.changed()},
                                      {"faces_dropped", r.repair.faces_dropped()}, {"validation", r.validation.to_json()},
                                      {"float32_rounding", c.rounding}, {"vertices", c.vertices}, {"faces", c.faces}};
            if (o->json) print_json(j);
            else print_repair_text(j);
            return 0;
          }};
}

}  // namespace sdm::cli
