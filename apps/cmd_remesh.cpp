#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/memory_budget.h"
#include "libstm/mesh/isotropic_remesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/spatial_order.h"
#include "libstm/geometry/triangle_bvh.h"

#include <cmath>
#include <memory>

namespace sdm::cli {

namespace {

// An edge length beyond a quarter of the model's diagonal collapses it to a speck (exit 0 with
// garbage, before the check); a tiny one asks for more triangles than memory holds (about A / (sqrt(3)/4
// L^2) triangles, 300 bytes each with the remesher's working copies).
void check_edge_length(const sdm::Mesh& input, double area, double edge, const std::string& max_memory) {
  const double diagonal = sdm::bounding_box_diagonal(input);
  if (edge > 0.25 * diagonal)
    throw sdm::InputError("edge length " + sdm::number(edge) + " is more than a quarter of the model's diagonal (" + sdm::number(diagonal) +
                          "): the remesh would collapse the model; use at most " + sdm::number(0.25 * diagonal));
  const double triangles = area / (std::sqrt(3.0) / 4 * edge * edge);
  check_memory(300 * triangles, max_memory, "remeshing at edge length " + sdm::number(edge) + " (" + sdm::number(triangles) + " triangles)",
               "use a longer --edge-length or a larger --factor");
}

// Remesh's summary (its --json object) as text.
void print_remesh_text(const nlohmann::json& j) {
  std::cout << j["output"].get<std::string>() << ": " << j["vertices"] << " vertices, " << j["faces"] << " faces (input "
            << j["input_vertices"] << "), edge length " << j["edge_length"].get<double>() << ", smallest angle "
            << j["min_angle_degrees"].get<double>() << " degrees\n";
}

}  // namespace

Command add_remesh_command(CLI::App& parent) {
  struct Opts {
    std::string mesh, out, max_memory;
    double edge = 0, factor = 1.0;
    int iterations = 8;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "remesh", "Isotropic remeshing: the same surface with new, well-shaped triangles of about one edge length\n"
                "(vertices projected back onto the input). Topology is kept; uv is not. Walls thinner than about\n"
                "the edge length can snap together: use a smaller --factor for thin CAD parts.");
  app->add_option("mesh", o->mesh, "Input mesh (.obj, .off, .ply, .stl, .glb, .gltf)")->required();
  app->add_option("-o,--output", o->out, "Output mesh")->required();
  app->add_option("--edge-length", o->edge, "Target edge length in model units (default: the equilateral edge for the input's area and vertex count, times --factor)")
      ->check(number_above(0, 1e30));
  app->add_option("--factor", o->factor, "Scale of the default target edge length")->capture_default_str()->check(number_in(0.1, 10.0));
  app->add_option("--iterations", o->iterations, "Remeshing iterations")->capture_default_str()->check(number_in(1, 100));
  add_max_memory_option(app, o->max_memory);
  add_repair_options(app);
  app->add_flag("--json", o->json, "Print one JSON object instead of text: the output's and the input's counts, the edge length, the smallest angle");
  return {app, [o]() {
            const sdm::Mesh input = load_mesh_min_part(o->mesh);
            const double area = sdm::surface_area(input);
            // Default: the edge of an equilateral mesh with as many vertices over the same area.
            const double edge = o->edge > 0 ? o->edge : sdm::equilateral_edge_length(area, double(input.n_vertices())) * o->factor;
            check_edge_length(input, area, edge, o->max_memory);
            const sdm::TriangleBvh bvh(sdm::vertex_matrix(input), sdm::face_matrix(input));
            sdm::Mesh mesh = input;
            mesh.release_halfedge_texcoords2D();
            sdm::isotropic_remesh(mesh, edge, o->iterations,
                                  [&](const Eigen::Vector3d& p) { return bvh.closest_point(p).point; });
            mesh = sdm::spatially_ordered(mesh);  // neighbours near in the file: every later pass reads faster
            sdm::write_mesh(mesh, o->out);
            const double rounding = note_float32_rounding(mesh, o->out);
            // One summary: --json prints it, the text reads it.
            const nlohmann::json j = {{"input", o->mesh},
                                      {"output", o->out},
                                      {"vertices", mesh.n_vertices()},
                                      {"faces", mesh.n_faces()},
                                      {"input_vertices", input.n_vertices()},
                                      {"input_faces", input.n_faces()},
                                      {"edge_length", edge},
                                      {"iterations", o->iterations},
                                      {"min_angle_degrees", sdm::min_triangle_angle_degrees(mesh)},
                                      {"float32_rounding", rounding}};
            if (o->json) print_json(j);
            else print_remesh_text(j);
            return 0;
          }};
}

}  // namespace sdm::cli
