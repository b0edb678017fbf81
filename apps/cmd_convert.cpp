#include "apps/commands.h"
#include "libstm/core/errors.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/validate_mesh.h"

#include <memory>

namespace sdm::cli {

Command add_convert_command(CLI::App& parent) {
  struct Opts {
    std::string mesh, out;
    bool strict = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "convert", "Validate a mesh and write it in another format (OBJ with uv and MTL, PLY, OFF, STL).\n"
                 "Refuses (exit 2, nothing written) a mesh the pipeline cannot take.");
  app->add_option("mesh", o->mesh, "Input mesh (.obj, .off, .ply, .stl, .glb, .gltf)")->required();
  app->add_option("-o,--output", o->out, "Output mesh; the format follows the extension")->required();
  app->add_flag("--strict", o->strict, "Also refuse meshes with tolerated findings (degenerate faces, isolated vertices, holes)");
  return {app, [o]() {
            sdm::MeshSoup soup = sdm::read_mesh_soup(o->mesh);
            sdm::MeshReport r = sdm::validate_mesh(soup);
            if (!r.usable()) throw sdm::InputError(r.refusal(o->mesh));
            if (o->strict) check_strict(r, o->mesh);
            for (const auto& f : r.findings) progress("note: " + std::to_string(f.count) + " " + f.kind + ", e.g. " + f.example);
            sdm::orient_outward(soup, r);
            sdm::Mesh mesh = sdm::build_mesh(soup);
            sdm::write_mesh(mesh, o->out, soup.texture);
            progress("wrote " + o->out + " (" + std::to_string(mesh.n_vertices()) + " vertices, " +
                     std::to_string(mesh.n_faces()) + " faces)");
            return 0;
          }};
}

}  // namespace sdm::cli
