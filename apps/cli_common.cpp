#include "apps/cli_common.h"

#include "apps/commands.h"
#include "libstm/core/errors.h"
#include "libstm/core/stopwatch.h"
#include "libstm/mesh/fill_holes.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/skeleton/extract_skeleton.h"

namespace sdm::cli {
namespace {

sdm::Layout read_layout_for(const sdm::Mesh& mesh, const std::string& path) {
  sdm::Layout layout = sdm::read_layout_json(path);
  if (layout.skeleton.vertex_node.size() != mesh.n_vertices())
    throw sdm::InputError("layout " + path + " was made for a mesh with " + std::to_string(layout.skeleton.vertex_node.size()) +
                          " vertices, this one has " + std::to_string(mesh.n_vertices()));
  return layout;
}

}  // namespace

LayoutForMesh layout_for(const sdm::Mesh& mesh, const LayoutSource& source) {
  LayoutForMesh r;
  if (!source.layout_file.empty()) {
    r.layout = read_layout_for(mesh, source.layout_file);
    return r;
  }
  const sdm::Progress stage_progress =
      source.announce_stages ? sdm::Progress([](const std::string& s) { progress("  " + s); }) : sdm::Progress(progress);
  sdm::Stopwatch clock;
  sdm::Skeleton skeleton;
  if (!source.skeleton_file.empty()) {
    skeleton = sdm::read_skeleton_json(source.skeleton_file);
  } else {
    if (source.announce_stages) progress("extracting the skeleton");
    skeleton = sdm::extract_skeleton(mesh, {}, stage_progress);
  }
  r.skeleton_seconds = clock.lap();
  sdm::LayoutOptions options = source.options;
  options.progress = stage_progress;
  if (source.announce_stages) progress("computing the layout");
  r.layout = sdm::compute_layout(mesh, skeleton, options);
  r.layout_seconds = clock.lap();
  r.computed = true;
  return r;
}

Mesh load_mesh_min_part(const std::string& path, double min_part, bool fill) {
  // Dropped before validation: a speck it would refuse (a stray flat triangle) does not stop the model.
  std::vector<std::string> dropped;
  sdm::Mesh mesh = sdm::load_mesh(path, nullptr, nullptr, nullptr, min_part, &dropped);
  for (const auto& d : dropped) progress("--min-part: dropped " + d);
  if (!fill) return mesh;
  const size_t before = mesh.n_vertices();
  const int loops = int(sdm::boundary_loops(sdm::face_matrix(mesh), int(before)).size());
  if (loops == 0) return mesh;
  mesh = sdm::fill_holes(mesh);
  progress("--fill-holes: closed " + std::to_string(loops) + " hole(s) with " + std::to_string(mesh.n_vertices() - before) + " vertices");
  return mesh;
}

void add_fill_holes_option(CLI::App* app, bool& value) {
  app->add_flag("--fill-holes", value,
                "Close an open mesh's holes first (smooth patches), so that the output is closed; by default the output\n"
                "keeps the holes open");
}

void add_min_part_option(CLI::App* app, double& value) {
  app->add_option("--min-part", value,
                  "Drop separate parts smaller than this fraction of the model's bounding-box diagonal (specks\n"
                  "too small for any texel), naming each")
      ->check(CLI::Range(0.0, 1.0));
}

}  // namespace sdm::cli
