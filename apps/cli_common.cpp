#include "apps/cli_common.h"

#include "apps/commands.h"
#include "libstm/core/errors.h"
#include "libstm/core/stopwatch.h"
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

}  // namespace sdm::cli
