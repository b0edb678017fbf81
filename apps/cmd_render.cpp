#include "apps/commands.h"
#include "libstm/errors.h"
#include "libstm/gl_context.h"
#include "libstm/image.h"
#include "libstm/mesh.h"
#include "libstm/render_mesh.h"
#include "libstm/render_skeleton.h"
#include "libstm/validate_mesh.h"

#include <memory>

namespace sdm_cli {

Command add_render_command(CLI::App& parent) {
  struct Opts {
    std::string mesh, output, texture, skeleton;
    int width = 800, height = 800;
    double azimuth = 30, elevation = 20;
    bool unlit = false, orthographic = false, flat = false, no_texture = false, json = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "render", "Render a mesh to a PNG image, offscreen (headless OpenGL through EGL).\n"
                "The camera frames the mesh's bounding box from the given azimuth and elevation; a mesh with uv\n"
                "is drawn with its texture (the map_Kd of its MTL, or --texture). Open meshes are drawn too.");
  app->add_option("mesh", o->mesh, "Input mesh (.obj, .off, .ply, .stl)")->required();
  app->add_option("-o,--output", o->output, "Output image (.png)")->required();
  app->add_option("--width", o->width, "Image width in pixels")->capture_default_str()->check(CLI::Range(1, 16384));
  app->add_option("--height", o->height, "Image height in pixels")->capture_default_str()->check(CLI::Range(1, 16384));
  app->add_option("--azimuth", o->azimuth, "Camera angle around the up (+y) axis in degrees; 0 looks along -z")
      ->capture_default_str();
  app->add_option("--elevation", o->elevation, "Camera angle above the horizontal plane in degrees")->capture_default_str();
  app->add_option("--texture", o->texture, "Texture image (.png) overriding the mesh's material; needs uv in the mesh");
  app->add_flag("--no-texture", o->no_texture, "Ignore the mesh's texture and draw it in a flat colour");
  app->add_flag("--unlit", o->unlit, "No shading: draw the texture (or flat) colour as it is, for pixel comparisons");
  app->add_flag("--orthographic", o->orthographic, "Orthographic instead of perspective (30 degree) projection");
  app->add_flag("--flat", o->flat, "Flat shading with face normals");
  app->add_option("--skeleton", o->skeleton, "Skeleton (.json from 'sdm skeleton') drawn over a semi-transparent mesh");
  app->add_flag("--json", o->json, "Print one JSON object describing the render");
  return {app, [o]() {
            // A picture is useful for any mesh, so unlike the pipeline commands, render also draws open
            // meshes (lighting is two-sided); only input the halfedge structure cannot hold is refused.
            stm::MeshSoup soup = stm::read_mesh_soup(o->mesh);
            stm::MeshReport report = stm::validate_mesh(soup);
            if (report.usable()) stm::orient_outward(soup, report);
            stm::Mesh mesh;
            try {
              mesh = stm::build_mesh(soup);
            } catch (const stm::InputError&) {
              throw stm::InputError(report.refusal(o->mesh));
            }
            const std::string material_texture = soup.texture;
            std::string texture_path = o->texture.empty() ? material_texture : o->texture;
            if (o->no_texture) texture_path.clear();
            stm::Image texture;
            if (!texture_path.empty()) {
              if (!mesh.has_halfedge_texcoords2D())
                throw stm::InputError("'" + o->mesh + "' has no texture coordinates, so texture '" + texture_path +
                                      "' cannot be applied");
              texture = stm::read_png(texture_path);
            }
            stm::GlContext gl;
            progress("GL renderer: " + gl.renderer() + " (" + gl.version() + ", " + gl.platform() + ")");
            stm::RenderOptions ro;
            ro.width = o->width;
            ro.height = o->height;
            ro.azimuth_deg = o->azimuth;
            ro.elevation_deg = o->elevation;
            ro.unlit = o->unlit;
            ro.orthographic = o->orthographic;
            ro.flat_shading = o->flat;
            if (!texture_path.empty()) ro.texture = &texture;
            std::vector<uint8_t> mask;
            stm::Image img;
            if (!o->skeleton.empty()) {
              const stm::Skeleton sk = stm::read_skeleton_json(o->skeleton);
              img = stm::render_with_skeleton(gl, mesh, sk, ro);
              stm::render_mesh(gl, mesh, ro, &mask);
            } else {
              img = stm::render_mesh(gl, mesh, ro, &mask);
            }
            stm::write_png(img, o->output);
            size_t covered = 0;
            for (uint8_t m : mask) covered += m ? 1 : 0;
            if (o->json) {
              print_json({{"output", o->output},
                          {"width", img.width},
                          {"height", img.height},
                          {"texture", texture_path},
                          {"covered_pixels", covered},
                          {"renderer", gl.renderer()},
                          {"gl_version", gl.version()},
                          {"platform", gl.platform()}});
            } else {
              std::cout << o->output << ": " << img.width << "x" << img.height << ", " << covered
                        << " object pixels" << (texture_path.empty() ? "" : ", texture " + texture_path) << "\n";
            }
            return 0;
          }};
}

}  // namespace sdm_cli
