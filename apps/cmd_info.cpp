#include "apps/commands.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/validate_mesh.h"

#include <iomanip>
#include <memory>

namespace sdm::cli {

Command add_info_command(CLI::App& parent) {
  struct Opts {
    std::string mesh;
    bool json = false;
    bool strict = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "info", "Describe a mesh: counts, parts, genus, boundary loops, bounding box and validation findings.\n"
              "Exits 2 when the mesh cannot go through the pipeline, so scripts can use it as a check.");
  app->add_option("mesh", o->mesh, "Input mesh (.obj, .off, .ply, .stl, .glb, .gltf)")->required();
  app->add_flag("--json", o->json, "Print one JSON object instead of text");
  app->add_flag("--strict", o->strict, "Exit 2 also for tolerated findings (degenerate faces, isolated vertices, holes)");
  return {app, [o]() {
            sdm::MeshSoup soup = sdm::read_mesh_soup(o->mesh);
            sdm::MeshReport r = sdm::validate_mesh(soup);
            if (r.usable()) sdm::orient_outward(soup, r);
            if (o->json) {
              auto j = r.to_json();
              j["file"] = o->mesh;
              j["uv"] = !soup.uv.empty();
              j["texture"] = soup.texture;
              print_json(j);
            } else {
              std::cout << o->mesh << "\n";
              std::cout << "  vertices        " << r.vertices << "\n";
              std::cout << "  faces           " << r.faces << "\n";
              std::cout << "  edges           " << r.edges << "\n";
              std::cout << "  parts           " << r.parts << "\n";
              std::cout << "  genus per part ";
              for (int g : r.genus_per_part) std::cout << ' ' << (g < 0 ? std::string("open") : std::to_string(g));
              std::cout << "\n  boundary loops  " << r.boundary_loops << "\n";
              std::cout << std::setprecision(6) << "  bounding box    [" << r.bbox_min.transpose() << "] - ["
                        << r.bbox_max.transpose() << "]\n";
              std::cout << "  uv              " << (soup.uv.empty() ? "no" : "yes") << "\n";
              if (!soup.texture.empty()) std::cout << "  texture         " << soup.texture << "\n";
              if (r.findings.empty()) std::cout << "  findings        none\n";
              for (const auto& f : r.findings)
                std::cout << "  " << (f.fatal ? "ERROR " : "note  ") << f.count << " " << f.kind << ", e.g. " << f.example
                          << (f.fatal ? "\n        fix: " + f.fix : "") << "\n";
              std::cout << "  pipeline        " << (r.usable() ? "ok" : "refused") << "\n";
            }
            if (!r.usable()) {
              if (!o->json) std::cerr << r.refusal(o->mesh) << std::endl;
              return 2;
            }
            if (o->strict) check_strict(r, o->mesh);
            return 0;
          }};
}

}  // namespace sdm::cli
