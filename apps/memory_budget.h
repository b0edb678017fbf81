#pragma once
// The memory budget: a command estimates what its options will allocate (decode's
// --lod, an atlas's --size, render's --width/--height/--views) and refuses beyond the budget up
// front, naming the estimate, instead of growing until the machine kills it.
#include "libstm/core/image.h"
#include "libstm/core/input_file.h"

#include <CLI/CLI.hpp>
#include <string>

namespace sdm::cli {

// Adds --max-memory (e.g. 8G, 512M, 2.5GB, or bytes) to a command; `value` receives the text.
void add_max_memory_option(CLI::App* app, std::string& value);

// Bytes of a --max-memory value; an empty value gives the default, three quarters of the
// machine's physical memory. Throws InputError for text that is not a size.
double memory_budget(const std::string& value);

// "1.5 GB", "340 MB": a byte count for a message.
std::string format_bytes(double bytes);

// Throws InputError when `estimate` bytes exceed the budget: "<what> needs about X, more than the
// memory budget of Y (...): <fix>, or raise --max-memory".
void check_memory(double estimate, const std::string& max_memory, const std::string& what, const std::string& fix);

// check_memory for an atlas of size^2 texels at `bytes_per_texel`: about 10 for the CPU stages
// (encode at 4096: 0.15 GB; stm --atlas-png at 4096: 0.15 GB), 60 where the GL draws the atlas
// (remap, texture transfer: framebuffer attachments and read-back, as for render).
void check_atlas_memory(int size, double bytes_per_texel, const std::string& max_memory);

// The budget read_layout_json and read_skeleton_json ask before parsing the JSON file `path`: the
// text and its tree (kJsonBytesPerFileByte times the file's size) within --max-memory.
sdm::ReadBudget json_budget(const std::string& max_memory, const std::string& path);

// The budget read_png asks before decoding the image `path` (a texture, an --stm atlas): its
// decoding's bytes (decode_image_bytes, from the image's header) within --max-memory.
sdm::ImageBudget image_budget(const std::string& max_memory, const std::string& path);

}  // namespace sdm::cli
