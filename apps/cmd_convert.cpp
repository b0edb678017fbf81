// sdm convert: a mesh written in another format, repaired as every command repairs it.
#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/convert_mesh.h"

#include <memory>

namespace sdm::cli {

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
  app->add_flag("--json", o->json, "Print one JSON object: the output, its vertex and face counts and what rounding to a float32 format (STL, glTF) cost");
  return {app, [o]() {
            const Converted c = convert(o->mesh, o->out, o->strict);
            // One summary: --json prints it, the text (a line on stderr) reads it.
            const nlohmann::json j = {{"input", o->mesh}, {"output", o->out}, {"float32_rounding", c.rounding},
                                      {"vertices", c.vertices}, {"faces", c.faces}};
            if (o->json) print_json(j);
            else print_written(j);
            return 0;
          }};
}

}  // namespace sdm::cli
