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
// a joint (assign_faces, segments.h); empty for the others.
std::string extension_note(const sdm::LayoutSegment& g) {
  if (g.extend_a <= 0 && g.extend_b <= 0) return "";
  std::ostringstream s;
  s << "  capsule runs on past";
  if (g.extend_a > 0) s << " a by " << std::setprecision(2) << std::defaultfloat << g.extend_a << " r";
  if (g.extend_a > 0 && g.extend_b > 0) s << " and";
  if (g.extend_b > 0) s << " b by " << std::setprecision(2) << std::defaultfloat << g.extend_b << " r";
  return s.str();
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
            if (o->json) {
              nlohmann::json j;
              j["mesh"] = o->mesh;
              j["layout"] = o->out;
              j["segments"] = layout.segments.size();
              j["coverage"] = layout.coverage;
              j["coverage_inner"] = layout.coverage_inner;
              j["stretch"] = c.stretch;
              j["seam_faces"] = c.seam_faces;
              j["size"] = layout.size;
              j["margin"] = layout.margin;
              j["scale"] = layout.scale;
              j["rectangles"] = nlohmann::json::array();
              for (const auto& g : layout.segments)
                j["rectangles"].push_back({{"segment", g.edge}, {"a", g.a}, {"b", g.b}, {"length", g.length}, {"radius", g.radius},
                                           {"rect", {g.x, g.y, g.w, g.h}}, {"rotated", g.rotated},
                                           {"extend", {g.extend_a, g.extend_b}}});
              print_json(j);
            } else {
              std::cout << o->mesh << "\n  segments        " << layout.segments.size() << "\n";
              std::cout << std::fixed << std::setprecision(4);
              for (const auto& g : layout.segments)
                std::cout << "    " << std::setw(3) << g.edge << "  nodes " << g.a << " -> " << g.b << "  L " << g.length << "  r "
                          << g.radius << "  rect " << g.w << "x" << g.h << " at (" << g.x << ", " << g.y << ")"
                          << (g.rotated ? " rotated" : "") << extension_note(g) << "\n";
              std::cout << "  atlas           " << layout.size << "^2 texels, margin " << layout.margin << "\n";
              std::cout << "  coverage        " << layout.coverage << " (inner " << layout.coverage_inner << ")\n";
              std::cout << "  L2 stretch      " << c.stretch << "\n";
              std::cout << "  seam faces      " << c.seam_faces << "\n";
              std::cout << "  layout          " << o->out << "\n";
            }
            return 0;
          }};
}

}  // namespace sdm::cli
