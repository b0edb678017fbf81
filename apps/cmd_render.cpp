#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/options.h"
#include "apps/view_up.h"
#include "libstm/core/limits.h"
#include "libstm/layout/draw_atlas.h"
#include "libstm/core/errors.h"
#include "libstm/render/gl_context.h"
#include "libstm/core/image.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/point_cloud.h"
#include "libstm/render/render_mesh.h"
#include "libstm/layout/layout_json.h"
#include "libstm/render/render_skeleton.h"
#include "libstm/render/render_stm.h"
#include "libstm/render/splat_mesh.h"
#include "libstm/mesh/validate_mesh.h"

#include <cmath>
#include <iomanip>
#include <limits>
#include <memory>

namespace sdm::cli {
namespace {

struct RenderArgs {
  std::string mesh, output, texture, skeleton, stm, layout;
  bool checker = false;
  int width = 800, height = 800, views = 1;
  double azimuth = 30, elevation = 20;
  bool unlit = false, orthographic = false, flat = false, no_texture = false, json = false, compare_uv = false;
  std::string max_memory;
  std::string up;
};

void declare_render_options(CLI::App* app, RenderArgs* o) {
  app->add_option("mesh", o->mesh, "Input mesh (.obj, .off, .ply, .stl, .glb, .gltf), or point cloud (.xyz, .pcd, PLY or OFF without faces)")->required();
  app->add_option("-o,--output", o->output, "Output image (.png)")->required();
  add_image_side_option(app, "--width", o->width, "Image width in pixels");
  add_image_side_option(app, "--height", o->height, "Image height in pixels");
  app->add_option("--azimuth", o->azimuth, "Camera angle around the up axis (--up) in degrees; 0 looks at the model's front (along -z for +y up, along +y for +z up)")
      ->capture_default_str()
      ->check(number_in(-360, 360));
  app->add_option("--elevation", o->elevation, "Camera angle above the horizontal plane in degrees")->capture_default_str()->check(number_in(-90, 90));
  app->add_option("--texture", o->texture, "Texture image (.png) overriding the mesh's material; needs uv in the mesh");
  app->add_flag("--no-texture", o->no_texture, "Ignore the mesh's texture and vertex colours and draw it in a flat colour");
  app->add_flag("--unlit", o->unlit, "No shading: draw the texture (or vertex, or flat) colour as it is, for pixel comparisons");
  app->add_flag("--orthographic", o->orthographic, "Orthographic instead of perspective (30 degree) projection");
  app->add_flag("--flat", o->flat, "Flat shading with face normals");
  app->add_option("--skeleton", o->skeleton, "Skeleton (.json from 'sdm skeleton') drawn over a semi-transparent mesh");
  app->add_option("--stm", o->stm, "Atlas (.png from 'sdm remap') to draw the mesh with, coordinates computed on the fly; needs --layout");
  app->add_option("--layout", o->layout, "Layout (.json) of the --stm atlas, made for this mesh");
  app->add_flag("--checker", o->checker,
                "With --layout (and no --stm): a checkerboard in STM coordinates, each segment in its colour, "
                "coordinates computed in the shaders (the standard look at a parameterization)");
  app->add_flag("--compare-uv", o->compare_uv,
                "With --stm: also draw the mesh with its own uv and texture, put both side by side and print the PSNR "
                "(dB, over the pixels either render covers; use with --unlit for a pure texture comparison)");
  app->add_option("--views", o->views, "Number of views around the up axis, starting at --azimuth (a contact sheet)")
      ->check(number_in(1, 64))
      ->capture_default_str();
  add_max_memory_option(app, o->max_memory);
  app->add_flag("--json", o->json, "Print one JSON object describing the render");
  add_up_option(app, o->up);
  add_repair_options(app);
}

// Before anything is drawn: the contact sheet must fit a PNG side (kMaxImageSide) and the views,
// the sheet and the framebuffers the memory budget: 12 bytes per view pixel (4 kept, 4 in the sheet,
// 1 of mask, the PNG's encoding) and 60 per framebuffer pixel (multisampled colour, float and depth
// attachments and their read-back); measured: 4096^2 one view 0.88 GB, 4 views of 2048^2 0.45 GB.
void check_render_size(const RenderArgs& o) {
  const int gap = 8;  // contact_sheet's and side_by_side's
  const int64_t cw = o.compare_uv ? 2 * int64_t(o.width) + gap : o.width, ch = o.height;
  int columns = 1;
  while (columns * columns < o.views) ++columns;
  if (o.compare_uv) columns = std::max(1, (columns + 1) / 2);
  columns = std::min(columns, o.views);
  const int rows = (o.views + columns - 1) / columns;
  const int64_t sw = columns * cw + (columns - 1) * gap, sh = rows * ch + (rows - 1) * gap;
  if (sw > sdm::kMaxImageSide || sh > sdm::kMaxImageSide)
    throw sdm::InputError("the picture of " + std::to_string(o.views) + " view(s) of " + std::to_string(o.width) + "x" +
                          std::to_string(o.height) + " would be " + std::to_string(sw) + "x" + std::to_string(sh) + " pixels, more than " +
                          std::to_string(sdm::kMaxImageSide) + " a side: use a smaller --width/--height or fewer --views");
  const double bytes = 12.0 * double(o.views) * double(cw) * double(ch) + 60.0 * double(o.width) * double(o.height);
  check_memory(bytes, o.max_memory, "rendering " + std::to_string(o.views) + " view(s) of " + std::to_string(o.width) + "x" +
                                        std::to_string(o.height),
               "use a smaller --width/--height or fewer --views");
}

// A picture is useful for any mesh, so unlike the pipeline commands, render also draws open
// meshes (lighting is two-sided); only input the halfedge structure cannot hold is refused.
// A glTF file's own texture: `material_texture` then names it with this marker.
const char* const kEmbeddedTexture = "(the texture embedded in the mesh file)";

sdm::Mesh load_any_mesh(const std::string& path, std::string* material_texture, sdm::Image* embedded, std::vector<Eigen::Vector3f>* colors) {
  sdm::MeshSoup soup = sdm::read_mesh_soup(path);
  sdm::LoadReport loaded = sdm::repair_and_validate(soup, load_options());  // the pipeline's repair, without its refusal
  for (const auto& line : sdm::repair_lines(loaded.repair)) progress(path + ": " + line);
  sdm::MeshReport& report = loaded.validation;
  if (report.usable()) sdm::orient_outward(soup, report);
  sdm::Mesh mesh;
  try {
    mesh = sdm::build_mesh(soup);
  } catch (const sdm::InputError&) {
    throw sdm::InputError(report.refusal(path));
  }
  colors->clear();
  if (soup.colors.size() == soup.points.size()) {  // build_mesh keeps the used points, in order
    const std::vector<char> used = sdm::used_points(soup);
    for (size_t i = 0; i < soup.colors.size(); ++i)
      if (used[i]) colors->push_back(soup.colors[i]);
  }
  *material_texture = soup.texture;
  if (soup.texture.empty() && !soup.texture_image.pixels.empty()) {
    *material_texture = kEmbeddedTexture;
    *embedded = std::move(soup.texture_image);
  }
  return mesh;
}

// A point cloud drawn as oriented disks (splat_mesh.h), normals estimated where the file has none,
// in the cloud's colours when it has them; `points` receives the number of points drawn.
sdm::Mesh load_cloud_splats(const RenderArgs& o, std::vector<Eigen::Vector3f>* colors, long* points) {
  if (!o.stm.empty() || o.checker || !o.texture.empty() || o.compare_uv)
    throw sdm::InputError("'" + o.mesh + "' is a point cloud: it is drawn as points (with --skeleton, its skeleton over them); "
                          "--stm, --checker, --texture and --compare-uv draw a mesh's maps (decode the cloud's map and render that)");
  sdm::CloudReport report;
  const sdm::PointCloud cloud = sdm::load_point_cloud(o.mesh, &report, true);
  if (report.normals_estimated) progress(o.mesh + ": normals estimated from the points' neighbours");
  sdm::Splats splats = sdm::splat_mesh(cloud.points, cloud.normals, o.no_texture ? std::vector<Eigen::Vector3f>{} : cloud.colors);
  *colors = std::move(splats.colors);
  *points = report.points;
  return std::move(splats.mesh);
}

// The texture drawn with the mesh's own uv: --texture, else the material's; none with --no-texture.
// Drawn from the STM, the mesh's own uv and texture only serve the --compare-uv picture.
std::string own_texture_path(const RenderArgs& o, const std::string& material_texture) {
  std::string texture_path = o.texture.empty() ? material_texture : o.texture;
  if (o.no_texture) texture_path.clear();
  if ((!o.stm.empty() || o.checker) && !o.compare_uv) texture_path.clear();
  return texture_path;
}

// Throws InputError for flags that do not go together.
void check_render_flags(const RenderArgs& o, const std::string& texture_path) {
  if (!o.stm.empty() && o.layout.empty()) throw sdm::InputError("--stm needs the atlas's --layout LAYOUT.json");
  if (o.checker && (o.layout.empty() || !o.stm.empty())) throw sdm::InputError("--checker needs --layout LAYOUT.json and no --stm");
  if (o.stm.empty() && !o.checker && (!o.layout.empty() || o.compare_uv))
    throw sdm::InputError("--layout and --compare-uv go with --stm ATLAS.png (or --layout with --checker)");
  if (o.compare_uv && texture_path.empty())
    throw sdm::InputError("--compare-uv needs the mesh's own texture: '" + o.mesh + "' names none (pass --texture)");
  if (!o.stm.empty() && !o.skeleton.empty()) throw sdm::InputError("--skeleton cannot be combined with --stm");
}

// The views drawn, and what they measured.
struct RenderedViews {
  std::vector<sdm::Image> cells;
  std::vector<double> psnrs;  // own uv vs STM, per view (--compare-uv)
  size_t covered = 0;         // object pixels over all views
};

// Draws the --views turntable: from the STM (layout and atlas given), with the skeleton, or plain.
RenderedViews render_views(const RenderArgs& o, sdm::GlContext& gl, const sdm::Mesh& mesh, sdm::RenderOptions ro,
                           const sdm::Layout* layout, const sdm::Image& atlas) {
  RenderedViews r;
  for (int view = 0; view < o.views; ++view) {
    ro.azimuth_deg = o.azimuth + 360.0 * view / o.views;
    std::vector<uint8_t> mask;
    sdm::Image img;
    if (layout) {
      img = sdm::render_stm(gl, mesh, *layout, atlas, ro, &mask);
      if (o.compare_uv) {
        std::vector<uint8_t> uv_mask;
        const sdm::Image uv_img = sdm::render_mesh(gl, mesh, ro, &uv_mask);
        const double p = sdm::psnr(uv_img, img, &(mask = sdm::mask_union(mask, uv_mask)));
        r.psnrs.push_back(p);
        progress("view " + std::to_string(view) + " (azimuth " + std::to_string(ro.azimuth_deg) + "): PSNR " + std::to_string(p) +
                 " dB");
        img = sdm::side_by_side({uv_img, img});
      }
    } else if (!o.skeleton.empty()) {
      const sdm::Skeleton sk = sdm::read_skeleton_json(o.skeleton, json_budget(o.max_memory, o.skeleton));
      img = sdm::render_with_skeleton(gl, mesh, sk, ro);
      sdm::render_mesh(gl, mesh, ro, &mask);
    } else {
      img = sdm::render_mesh(gl, mesh, ro, &mask);
    }
    for (uint8_t m : mask) r.covered += m ? 1 : 0;
    r.cells.push_back(std::move(img));
  }
  return r;
}

// One cell, or the contact sheet of all (as square as it gets; a --compare-uv cell is a pair).
sdm::Image contact_sheet_of(const RenderArgs& o, const std::vector<sdm::Image>& cells) {
  int columns = 1;
  while (columns * columns < o.views) ++columns;
  if (o.compare_uv) columns = std::max(1, (columns + 1) / 2);  // each cell is a pair
  return cells.size() == 1 ? cells[0] : sdm::contact_sheet(cells, columns);
}

// Render's summary (its --json object) as text.
void print_render_text(const nlohmann::json& j) {
  const std::string texture = j["texture"].get<std::string>();
  std::cout << j["output"].get<std::string>() << ": " << j["width"] << "x" << j["height"] << ", " << j["covered_pixels"] << " object pixels"
            << (j.contains("stm") ? ", STM " + texture : (texture.empty() ? "" : ", texture " + texture))
            << (j["vertex_colors"].get<bool>() ? ", vertex colours" : "")
            << (j.contains("points") ? ", " + std::to_string(j["points"].get<long>()) + " points as disks" : "") << "\n";
  if (j.contains("psnr"))
    std::cout << std::fixed << std::setprecision(2) << "PSNR own uv vs STM: min " << j["psnr"]["min"].get<double>() << " dB, mean "
              << j["psnr"]["mean"].get<double>() << " dB over " << j["psnr"]["views"].size() << " view(s)\n";
}

// The summary of a render: printed as JSON (--json) or as text.
void report_render(const RenderArgs& o, const sdm::GlContext& gl, const sdm::Image& img, const RenderedViews& v,
                   const std::string& texture_path, bool vertex_colors, const ViewUp& up, long points) {
  double min_psnr = std::numeric_limits<double>::infinity(), mean_psnr = 0;
  for (double p : v.psnrs) min_psnr = std::min(min_psnr, p), mean_psnr += p / v.psnrs.size();
  nlohmann::json j = {{"output", o.output},
                      {"width", img.width},
                      {"height", img.height},
                      {"views", o.views},
                      {"texture", o.stm.empty() ? texture_path : o.stm},
                      {"vertex_colors", vertex_colors},
                      {"covered_pixels", v.covered},
                      {"up", up.name},
                      {"up_from", up.known() ? up.from : "assumed (give --up for a file of another convention)"},
                      {"renderer", gl.renderer()},
                      {"gl_version", gl.version()},
                      {"platform", gl.platform()}};
  if (!o.stm.empty()) {
    j["stm"] = o.stm;
    j["layout"] = o.layout;
  }
  if (o.compare_uv) j["psnr"] = {{"views", v.psnrs}, {"min", min_psnr}, {"mean", mean_psnr}};
  if (points) j["points"] = points;
  if (o.json) print_json(j);
  else print_render_text(j);
}

int run_render(const RenderArgs& o) {
  check_render_size(o);
  const ViewUp up = view_up(o.up, o.mesh);
  std::string material_texture;
  sdm::Image embedded;
  std::vector<Eigen::Vector3f> colors;
  long points = 0;  // of a point cloud
  const sdm::Mesh mesh = sdm::is_point_cloud_file(o.mesh) ? load_cloud_splats(o, &colors, &points)
                                                          : load_any_mesh(o.mesh, &material_texture, &embedded, &colors);
  const std::string texture_path = own_texture_path(o, material_texture);
  sdm::Image texture;
  if (!texture_path.empty()) {
    if (!mesh.has_halfedge_texcoords2D())
      throw sdm::InputError("'" + o.mesh + "' has no texture coordinates, so texture '" + texture_path + "' cannot be applied");
    texture = texture_path == kEmbeddedTexture ? std::move(embedded) : sdm::read_png(texture_path, image_budget(o.max_memory, texture_path));
  }
  check_render_flags(o, texture_path);
  const bool from_stm = !o.stm.empty() || o.checker;
  sdm::Layout layout;
  sdm::Image atlas;
  if (from_stm) {
    layout = sdm::read_layout_json(o.layout, json_budget(o.max_memory, o.layout));
    atlas = o.checker ? sdm::checker_atlas(layout, std::max(4, layout.size / 64)) : sdm::read_png(o.stm, image_budget(o.max_memory, o.stm));
  }
  sdm::GlContext gl;
  progress("GL renderer: " + gl.renderer() + " (" + gl.version() + ", " + gl.platform() + ")");
  sdm::RenderOptions ro;
  ro.frame = sdm::up_view_frame(up.axis);
  ro.width = o.width;
  ro.height = o.height;
  ro.elevation_deg = o.elevation;
  ro.unlit = o.unlit;
  ro.orthographic = o.orthographic;
  ro.flat_shading = o.flat;
  if (!texture_path.empty()) ro.texture = &texture;
  const bool draw_colors = !colors.empty() && texture_path.empty() && !o.no_texture && !from_stm;
  if (draw_colors) ro.vertex_colors = &colors;
  const RenderedViews views = render_views(o, gl, mesh, ro, from_stm ? &layout : nullptr, atlas);
  const sdm::Image img = contact_sheet_of(o, views.cells);
  sdm::write_png(img, o.output);
  report_render(o, gl, img, views, texture_path, draw_colors, up, points);
  return 0;
}

}  // namespace

Command add_render_command(CLI::App& parent) {
  auto o = std::make_shared<RenderArgs>();
  auto* app = parent.add_subcommand(
      "render", "Render a mesh to a PNG image, offscreen (headless OpenGL through EGL).\n"
                "The camera frames the mesh's bounding box from the given azimuth and elevation; a mesh with uv\n"
                "is drawn with its texture (the map_Kd of its MTL, or --texture), a mesh with a colour per vertex\n"
                "(PLY red/green/blue, glTF COLOR_0, OBJ 'v x y z r g b') in those colours. Open meshes are drawn too.\n"
                "With --stm ATLAS.png --layout LAYOUT.json the mesh is drawn from its skeleton texture map, with\n"
                "STM coordinates computed in the shaders from positions and the layout only (any uv is ignored);\n"
                "--compare-uv then also draws it with its own uv and texture, writes both side by side (own uv\n"
                "left, STM right) and prints the PSNR between them over the object's pixels.\n"
                "--views N draws a turntable (N azimuths, 360/N degrees apart) as one contact sheet.\n"
                "A point cloud is drawn as one small disk per point, square to its normal (estimated when the file\n"
                "has none), with --skeleton its skeleton over them.");
  declare_render_options(app, o.get());
  return {app, [o]() { return run_render(*o); }};
}

}  // namespace sdm::cli
