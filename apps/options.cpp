#include "apps/options.h"

#include "libstm/core/errors.h"
#include "libstm/layout/layout_json.h"
#include "libstm/mesh/check_mesh_file.h"

#include <filesystem>

namespace sdm::cli {

CLI::Option* add_size_option(CLI::App* app, int& size, const std::string& help, int lo, int hi) {
  return app->add_option("--size", size, help)->capture_default_str()->check(number_in(lo, hi));
}

CLI::Option* add_margin_option(CLI::App* app, int& margin, const std::string& help) {
  return app->add_option("--margin", margin, help)->capture_default_str()->check(number_in(0, 256));
}

CLI::Option* add_image_side_option(CLI::App* app, const std::string& name, int& side, const std::string& help) {
  return app->add_option(name, side, help)->capture_default_str()->check(number_in(1, sdm::kMaxImageSide));
}

void add_layout_options(CLI::App* app, LayoutSource& source, LayoutFlags flags) {
  const std::string computed = flags.layout_file ? " (when the layout is computed)" : "";
  if (flags.layout_file)
    app->add_option("--layout", source.layout_file,
                    "Use this layout (.json from 'sdm stm' or 'sdm remap', made for this mesh) instead of computing one");
  if (flags.skeleton_file)
    app->add_option("--skeleton", source.skeleton_file,
                    "Use this skeleton (.json from 'sdm skeleton', made for this mesh) instead of extracting one with the\n"
                    "default options of 'sdm skeleton'");
  add_size_option(app, source.options.size, "Atlas width and height in texels" + computed);
  if (flags.margin) add_margin_option(app, source.options.margin, "Texels of margin around every rectangle" + computed);
}

LayoutSource layout_defaults(int size, int margin, bool announce_stages) {
  LayoutSource source;
  source.options.size = size;
  source.options.margin = margin;
  source.announce_stages = announce_stages;
  return source;
}

void check_layout_memory(LayoutSource& source, double bytes_per_texel, const std::string& max_memory) {
  source.read.reset();  // a command run again reads its file again
  if (!source.layout_file.empty()) source.read = sdm::read_layout_json(source.layout_file, json_budget(max_memory, source.layout_file));
  check_atlas_memory(source.read ? source.read->size : source.options.size, bytes_per_texel, max_memory);
}

std::map<int, int> parse_segment_levels(const std::vector<std::string>& items) {
  std::map<int, int> out;
  for (const auto& s : items) {
    const std::string form = "--lod-segment '" + s + "' is not of the form ID=LEVEL (e.g. 3=1)";
    const IdValue iv = parse_id_value(s, form);
    out[iv.id] = parse_whole_number(iv.value, form);
  }
  return out;
}

void check_strict(const sdm::MeshReport& r, const std::string& path) {
  for (const auto& f : r.findings)
    if (f.id == "degenerate_faces" || f.id == "isolated_vertices" || f.id == "boundary_edges")
      throw sdm::InputError("mesh " + path + " has " + std::to_string(f.count) + " " + f.kind + ", e.g. " + f.example +
                            " (refused by --strict). Fix: " + f.fix);
}

bool has_extension(const std::string& path, std::initializer_list<const char*> extensions) {
  const std::string ext = sdm::lower_extension(path);
  for (const char* e : extensions)
    if (ext == e) return true;
  return false;
}

std::string sibling(const std::string& path, const std::string& suffix) {
  const std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + suffix)).string();
}

}  // namespace sdm::cli
