#include "apps/cli_common.h"
#include "apps/commands.h"
#include "libstm/mesh/isotropic_remesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/primitives.h"

#include <memory>

namespace sdm::cli {
namespace {

// Primitive's summary (its --json object) as text.
void print_primitive_text(const nlohmann::json& j) {
  std::cout << j["name"].get<std::string>() << " -> " << j["file"].get<std::string>() << "\n";
  std::cout << "  vertices   " << j["vertices"] << "\n  faces      " << j["faces"] << "\n  genus      " << j["genus"] << "\n";
  std::cout << "  min angle  " << j["min_angle_degrees"].get<double>() << " degrees\n";
}

}  // namespace

Command add_primitive_command(CLI::App& parent) {
  struct Opts {
    std::string name, output;
    int resolution = 0;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  std::string names;
  for (const auto& n : sdm::primitive_names()) names += (names.empty() ? "" : ", ") + n;
  auto* app = parent.add_subcommand(
      "primitive", "Write one of the paper's test shapes (or an analytic cylinder/capsule) as a closed 2-manifold\n"
                   "triangle mesh with well-shaped triangles. Names: " + names);
  app->add_option("name", o->name, "Shape: " + names)->required();
  app->add_option("-o,--output", o->output, "Output mesh (.obj, .off, .ply, .stl, .glb, .gltf)")->required();
  app->add_option("--resolution", o->resolution,
                  "Approximate number of vertices (0 = the paper's count for its shapes, 1200 for cylinder/capsule)")
      ->check(number_in(0, 1e6));
  app->add_flag("--json", o->json, "Print one JSON object instead of text");
  return {app, [o]() {
            sdm::Mesh mesh = sdm::make_primitive(o->name, o->resolution);
            sdm::write_mesh(mesh, o->output);
            const long v = static_cast<long>(mesh.n_vertices()), e = static_cast<long>(mesh.n_edges()),
                       f = static_cast<long>(mesh.n_faces());
            const long genus = (2 - (v - e + f)) / 2;  // every primitive is one closed part
            const double min_angle = sdm::min_triangle_angle_degrees(mesh);
            // One summary: --json prints it, the text reads it.
            const nlohmann::json j = {{"name", o->name}, {"file", o->output}, {"vertices", v},        {"faces", f},
                                      {"edges", e},      {"genus", genus},    {"min_angle_degrees", min_angle}};
            if (o->json) print_json(j);
            else print_primitive_text(j);
            return 0;
          }};
}

}  // namespace sdm::cli
