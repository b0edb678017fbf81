#include "apps/output_paths.h"

#include "libstm/core/errors.h"

#include <filesystem>
#include <set>
#include <vector>

namespace fs = std::filesystem;

namespace sdm::cli {
namespace {

struct NamedPath {
  std::string option, path;
};

std::string option_name(const CLI::Option& o) {
  return o.get_lnames().empty() ? o.get_name(true) : o.get_lnames().front();
}

void check_one_output(const NamedPath& out, const std::vector<NamedPath>& inputs) {
  std::error_code ec;
  const std::string what = "cannot write " + out.path + " (--" + out.option + "): ";
  const fs::path p(out.path);
  if (fs::is_directory(p, ec)) throw InputError(what + "it is a folder; name a file in it");
  if (fs::exists(p, ec) && !fs::is_regular_file(p, ec))
    throw InputError(what + "it exists and is not a regular file (a device, pipe or socket); name a file to write");
  if (p.has_parent_path() && !fs::is_directory(p.parent_path(), ec))
    throw InputError(what + "folder " + p.parent_path().string() + " does not exist");
  for (const auto& in : inputs)
    if (fs::exists(p, ec) && fs::equivalent(p, in.path, ec))
      throw InputError(what + "it is also the input " + in.path + " (" + in.option + "); name another output file");
}

}  // namespace

bool is_output_option(const std::string& n) {
  static const std::set<std::string> outputs = {"output", "png", "obj", "uv-obj", "atlas-png", "write-skeleton",
                                                "correspondence", "vertex-colors"};
  return outputs.count(n) > 0;
}

namespace {

// The command's outputs and the existing files among its other option values (its inputs).
void command_paths(const CLI::App& command, std::vector<NamedPath>& inputs, std::vector<NamedPath>& outputs) {
  for (const CLI::Option* o : command.get_options()) {
    if (o->count() == 0) continue;
    const std::string name = option_name(*o);
    for (const std::string& value : o->results()) {
      std::error_code ec;
      if (is_output_option(name)) outputs.push_back({name, value});
      else if (fs::is_regular_file(value, ec)) inputs.push_back({name, value});
    }
  }
}

}  // namespace

OutputsBefore record_outputs(const CLI::App& command) {
  std::vector<NamedPath> inputs, outputs;
  command_paths(command, inputs, outputs);
  OutputsBefore before;
  for (const auto& out : outputs) {
    std::error_code ec;
    const auto t = fs::last_write_time(out.path, ec);
    before.emplace_back(out.path, ec ? std::nullopt : std::optional<fs::file_time_type>(t));
  }
  return before;
}

void remove_written_outputs(const OutputsBefore& before) {
  for (const auto& [path, time] : before) {
    std::error_code ec;
    const auto now = fs::last_write_time(path, ec);
    if (!ec && (!time || now != *time)) fs::remove(path, ec);
  }
}

void check_output_paths(const CLI::App& command) {
  std::vector<NamedPath> inputs, outputs;
  command_paths(command, inputs, outputs);
  std::set<std::string> seen;
  for (const auto& out : outputs) {
    check_one_output(out, inputs);
    const std::string key = fs::weakly_canonical(out.path).string();
    if (!seen.insert(key).second)
      throw InputError("cannot write " + out.path + " (--" + out.option + "): another output of the command names the same file");
  }
}

}  // namespace sdm::cli
