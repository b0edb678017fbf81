#pragma once
// The options several commands share, declared and read in one place: where a layout comes from
// (--layout, --skeleton, --size, --margin), image sides within limits.h, the memory an atlas needs
// against --max-memory, ID=VALUE items of repeatable options, and the extension an output must have.
// What they throw is an InputError (exit 2) that names the option.
#include "apps/cli_common.h"
#include "apps/memory_budget.h"
#include "libstm/core/id_value.h"
#include "libstm/core/limits.h"
#include "libstm/mesh/validate_mesh.h"

#include <CLI/CLI.hpp>
#include <initializer_list>
#include <map>
#include <string>
#include <vector>

namespace sdm::cli {

// --size: an atlas side in texels, from `lo` to `hi` (kMaxImageSide unless the command draws less).
CLI::Option* add_size_option(CLI::App* app, int& size, const std::string& help, int lo = 16, int hi = sdm::kMaxImageSide);
// --margin: texels around every rectangle of the atlas, 0 to 256.
CLI::Option* add_margin_option(CLI::App* app, int& margin, const std::string& help = "Texels of margin around every rectangle");
// A picture's --width or --height: 1 to kMaxImageSide pixels.
CLI::Option* add_image_side_option(CLI::App* app, const std::string& name, int& side, const std::string& help);

// The options of where a command's layout comes from, bound to `source` (its options' size and
// margin, as set before the call, are the defaults): --size always, and --layout FILE, --skeleton
// FILE and --margin where the command takes them.
struct LayoutFlags {
  bool layout_file = false, skeleton_file = false, margin = false;
};
void add_layout_options(CLI::App* app, LayoutSource& source, LayoutFlags flags);
// A LayoutSource whose computed layout has `size` and `margin` (the defaults add_layout_options shows);
// `announce_stages` as LayoutSource's.
LayoutSource layout_defaults(int size, int margin, bool announce_stages = false);

// Refuses, before any work, an atlas beyond the memory budget (check_atlas_memory at
// `bytes_per_texel`): the computed layout's --size, or the size of the layout file given, read
// within the budget (json_budget) into source.read, where layout_for takes it from.
void check_layout_memory(LayoutSource& source, double bytes_per_texel, const std::string& max_memory);

// ID=VALUE items (libstm/core/id_value.h; --match's: parse_node_pairs in share_skeletons.h):
// --lod-segment ID=LEVEL items, as a map from segment to level.
std::map<int, int> parse_segment_levels(const std::vector<std::string>& items);

// --strict of convert and info: the tolerated findings (validate_mesh.h, by their ids: degenerate
// faces, isolated vertices, boundary edges) refuse the input too, naming the first.
void check_strict(const sdm::MeshReport& r, const std::string& path);

// Whether `path` ends in one of `extensions` (".obj", ...), in any case (FOO.OBJ is an .obj file).
bool has_extension(const std::string& path, std::initializer_list<const char*> extensions);
// `path` with its extension replaced by `suffix` (OUT.obj, "_atlas.png" -> OUT_atlas.png).
std::string sibling(const std::string& path, const std::string& suffix);

}  // namespace sdm::cli
