#include "apps/cli_common.h"
#include "apps/cloud_input.h"
#include "apps/commands.h"
#include "apps/options.h"
#include "libstm/layout/draw_atlas.h"
#include "libstm/core/errors.h"
#include "libstm/layout/layout_json.h"
#include "libstm/layout/stm_coordinates.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/point_cloud.h"
#include "libstm/skeleton/skeleton.h"

#include <filesystem>
#include <iomanip>
#include <memory>
#include <sstream>

namespace sdm::cli {

namespace {

// "  capsule runs on past a by 1.5 r" and the like, for the segments whose caps would fold faces at
// a joint (assign_faces, segments.h; `extend`: past a and past b, in radii); empty for the others.
std::string extension_note(const nlohmann::json& extend) {
  const double a = extend[0].get<double>(), b = extend[1].get<double>();
  if (a <= 0 && b <= 0) return "";
  std::ostringstream s;
  s << "  capsule runs on past";
  if (a > 0) s << " a by " << std::setprecision(2) << std::defaultfloat << a << " r";
  if (a > 0 && b > 0) s << " and";
  if (b > 0) s << " b by " << std::setprecision(2) << std::defaultfloat << b << " r";
  return s.str();
}

// The summary of stm (its --json object) as text.
void print_stm_text(const nlohmann::json& j) {
  auto num = [](const nlohmann::json& x) { return x.get<double>(); };
  std::cout << j["mesh"].get<std::string>() << "\n  segments        " << j["segments"] << "\n";
  std::cout << std::fixed << std::setprecision(4);
  for (const auto& g : j["rectangles"])
    std::cout << "    " << std::setw(3) << g["segment"].get<int>() << "  nodes " << g["a"] << " -> " << g["b"] << "  L "
              << num(g["length"]) << "  r " << num(g["radius"]) << "  rect " << g["rect"][2] << "x" << g["rect"][3] << " at ("
              << g["rect"][0] << ", " << g["rect"][1] << ")" << (g["rotated"].get<bool>() ? " rotated" : "") << extension_note(g["extend"])
              << "\n";
  std::cout << "  atlas           " << j["size"] << "^2 texels, margin " << j["margin"] << "\n";
  std::cout << "  coverage        " << num(j["coverage"]) << " (inner " << num(j["coverage_inner"]) << ")\n";
  std::cout << "  L2 stretch      " << num(j["stretch"]) << "\n";
  std::cout << "  seam faces      " << j["seam_faces"] << "\n";
  std::cout << "  layout          " << j["layout"].get<std::string>() << "\n";
}

}  // namespace

Command add_stm_command(CLI::App& parent) {
  struct Opts {
    std::string mesh, out, uv_obj, atlas_png, max_memory;
    LayoutSource layout = layout_defaults(1024, 4);
    double min_part = 0;
    bool fill_holes = false;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "stm", "Compute the skeleton texture map layout of a mesh: one capsule per skeleton segment, its\n"
             "rectangle packed into one square atlas. Writes the layout (JSON, it includes the skeleton) and\n"
             "prints the segments, the atlas coverage and the L2 stretch of the STM coordinates.");
  app->add_option("mesh", o->mesh,
                  "Input mesh (.obj, .off, .ply, .stl, .glb, .gltf), closed and manifold, or point cloud (.xyz, .pcd, .ply or .off "
                  "without faces: the layout of the surface its points describe, around the cloud's skeleton)")->required();
  app->add_option("-o,--output", o->out, "Layout file to write (.json, format sdm-layout)")->required();
  add_layout_options(app, o->layout, {false, true, true});
  app->add_option("--uv-obj", o->uv_obj, "Also write the mesh with its STM coordinates as uv (OBJ; seam vertices duplicated)");
  app->add_option("--atlas-png", o->atlas_png, "Also draw the atlas: rectangles and each segment's triangles in its colour (PNG)");
  add_min_part_option(app, o->min_part);
  add_repair_options(app);
  add_fill_holes_option(app, o->fill_holes);
  add_max_memory_option(app, o->max_memory);
  app->add_flag("--json", o->json, "Print one JSON object instead of text");
  return {app, [o]() {
            check_layout_memory(o->layout, 10, o->max_memory);
            if (sdm::is_point_cloud_file(o->mesh))
              return cloud_stm(o->mesh, o->out, o->layout.options.size, o->layout.options.margin, o->uv_obj, o->json);
            sdm::Mesh mesh = load_mesh_min_part(o->mesh, o->min_part, o->fill_holes);
            const sdm::Layout layout = layout_for(mesh, o->layout, o->max_memory).layout;
            const sdm::StmCoordinates c = sdm::stm_coordinates(mesh, layout);
            sdm::write_layout_json(layout, o->out);
            if (!o->atlas_png.empty()) sdm::write_atlas_png(mesh, layout, c.face_segment, o->atlas_png);
            if (!o->uv_obj.empty()) sdm::write_mesh(c.mesh, o->uv_obj, o->atlas_png.empty() ? "" : std::filesystem::absolute(o->atlas_png).string());
            nlohmann::json rectangles = nlohmann::json::array();
            for (const auto& g : layout.segments)
              rectangles.push_back({{"segment", g.edge}, {"a", g.a}, {"b", g.b}, {"length", g.length}, {"radius", g.radius},
                                    {"rect", {g.x, g.y, g.w, g.h}}, {"rotated", g.rotated}, {"extend", {g.extend_a, g.extend_b}}});
            // One summary: --json prints it, the text reads it.
            const nlohmann::json j = {{"mesh", o->mesh}, {"layout", o->out}, {"segments", layout.segments.size()},
                                      {"coverage", layout.coverage}, {"coverage_inner", layout.coverage_inner}, {"stretch", c.stretch},
                                      {"seam_faces", c.seam_faces}, {"size", layout.size}, {"margin", layout.margin},
                                      {"scale", layout.scale}, {"rectangles", rectangles}};
            if (o->json) print_json(j);
            else print_stm_text(j);
            return 0;
          }};
}

}  // namespace sdm::cli
