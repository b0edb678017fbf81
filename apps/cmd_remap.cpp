#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/options.h"
#include "libstm/core/errors.h"
#include "libstm/render/gl_context.h"
#include "libstm/core/image.h"
#include "libstm/core/stopwatch.h"
#include "libstm/layout/layout_json.h"
#include "libstm/mesh/mesh.h"
#include "libstm/render/render_atlas.h"

#include <filesystem>
#include <memory>

namespace sdm::cli {
namespace {

// Remap's summary (its --json object) as text.
void print_remap_text(const nlohmann::json& j) {
  std::cout << j["atlas"].get<std::string>() << ": " << j["size"] << "^2 atlas, " << j["segments"] << " segments, "
            << int(100 * j["covered_texels"].get<double>() + 0.5) << " % of texels drawn from the surface\n"
            << "  layout " << j["layout"].get<std::string>() << (j["layout_written"].get<bool>() ? " (written)" : " (given)") << "\n"
            << "  texture " << j["texture"].get<std::string>() << "\n";
}

}  // namespace

Command add_remap_command(CLI::App& parent) {
  struct Opts {
    std::string mesh, output, texture, max_memory;
    LayoutSource layout = layout_defaults(2048, 8);
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "remap", "Remap the texture of a textured mesh into its skeleton texture map (STM): every segment's\n"
               "triangles drawn into its atlas rectangle at their capsule coordinates, margins filled with the\n"
               "surface next to them, empty texels filled from their neighbours (headless OpenGL through EGL).\n"
               "Writes the atlas PNG and, unless --layout is given, the layout next to it (ATLAS.json; the\n"
               "skeleton is extracted and the layout computed first). Render the result with\n"
               "'sdm render MESH --stm ATLAS.png --layout ATLAS.json' (no uv needed).");
  app->add_option("mesh", o->mesh, "Input mesh with uv (.obj with its MTL), closed and manifold")->required();
  app->add_option("-o,--output", o->output, "Atlas image to write (.png)")->required();
  app->add_option("--texture", o->texture, "Source texture (.png); default: the map_Kd of the mesh's MTL");
  add_layout_options(app, o->layout, {true, false, true});
  app->add_flag("--json", o->json, "Print one JSON object instead of text");
  add_max_memory_option(app, o->max_memory);
  add_repair_options(app);
  return {app, [o]() {
            check_layout_memory(o->layout, 60, o->max_memory);
            sdm::LoadedMesh loaded = load_input(o->mesh);
            const std::string material = loaded.texture;
            const sdm::Mesh mesh = std::move(loaded.mesh);
            const std::string texture_path = o->texture.empty() ? material : o->texture;
            if (texture_path.empty())
              throw sdm::InputError("'" + o->mesh + "' names no texture in its material: pass --texture TEX.png");
            if (!mesh.has_halfedge_texcoords2D())
              throw sdm::InputError("'" + o->mesh + "' has no texture coordinates, so its texture cannot be remapped");
            const sdm::Image source = sdm::read_png(texture_path, image_budget(o->max_memory, texture_path));
            const LayoutForMesh got = layout_for(mesh, o->layout, o->max_memory);
            const sdm::Layout& layout = got.layout;
            const std::string layout_path =
                got.computed ? std::filesystem::path(o->output).replace_extension(".json").string() : o->layout.layout_file;
            const sdm::Stopwatch clock;
            sdm::GlContext gl;
            progress("GL renderer: " + gl.renderer() + " (" + gl.version() + ", " + gl.platform() + ")");
            sdm::AtlasOptions ao;
            ao.progress = progress;
            std::vector<uint8_t> covered;
            const sdm::Image atlas = sdm::render_atlas(gl, mesh, layout, source, ao, &covered);
            const double t_atlas = clock.seconds();
            sdm::write_png(atlas, o->output);
            if (got.computed) sdm::write_layout_json(layout, layout_path);
            size_t n = 0;
            for (uint8_t c : covered) n += c ? 1 : 0;
            const double covered_fraction = double(n) / double(covered.size());
            // One summary: --json prints it, the text reads it.
            const nlohmann::json j = {{"atlas", o->output},
                                      {"layout", layout_path},
                                      {"layout_written", got.computed},
                                      {"texture", texture_path},
                                      {"size", layout.size},
                                      {"segments", layout.segments.size()},
                                      {"covered_texels", covered_fraction},
                                      {"coverage", layout.coverage},
                                      {"seconds", {{"skeleton", got.skeleton_seconds}, {"layout", got.layout_seconds}, {"atlas", t_atlas}}},
                                      {"renderer", gl.renderer()}};
            if (o->json) print_json(j);
            else print_remap_text(j);
            return 0;
          }};
}

}  // namespace sdm::cli
