#include "apps/commands.h"
#include "apps/hand_over.h"
#include "apps/output_paths.h"
#include "libstm/core/atomic_file.h"
#include "libstm/core/errors.h"
#include "libstm/core/version.h"

#include <algorithm>
#include <iostream>
#include <iterator>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct Entry {
  const char* name;
  sdm::cli::Command (*add)(CLI::App&);
};

// Pipeline order: --help lists them so.
const Entry kCommands[] = {
    {"info", sdm::cli::add_info_command},
    {"convert", sdm::cli::add_convert_command},
    {"repair", sdm::cli::add_repair_command},
    {"remesh", sdm::cli::add_remesh_command},
    {"primitive", sdm::cli::add_primitive_command},
    {"skeleton", sdm::cli::add_skeleton_command},
    {"stm", sdm::cli::add_stm_command},
#ifndef SDM_FRONT
    {"remap", sdm::cli::add_remap_command},
    {"render", sdm::cli::add_render_command},
    {"encode", sdm::cli::add_encode_command},
    {"decode", sdm::cli::add_decode_command},
    {"pose", sdm::cli::add_pose_command},
    {"roundtrip", sdm::cli::add_roundtrip_command},
    {"compare", sdm::cli::add_compare_command},
    {"transfer", sdm::cli::add_transfer_command},
    {"correspond", sdm::cli::add_correspond_command},
    {"bench", sdm::cli::add_bench_command},
#endif
};

// The commands to set up: only the one the command line names, else all of them (--help,
// --version, a misspelt command or none). CLI11 builds every option's strings, validators and
// callbacks when it is declared: setting up all the light commands took 0.2 ms of the 3.0-3.2 ms
// that `sdm skeleton` needs to start and refuse a missing file, 1.5 % of a small mesh's run.
std::vector<sdm::cli::Command> set_up_commands(CLI::App& app, int argc, char** argv) {
  const std::string first = argc > 1 ? argv[1] : "";
  const bool named = std::any_of(std::begin(kCommands), std::end(kCommands), [&](const Entry& e) { return first == e.name; });
  std::vector<sdm::cli::Command> commands;
  for (const Entry& e : kCommands) {
    if (named && first != e.name) continue;
    commands.push_back(e.add(app));
    if (commands.back().app->get_name() != e.name)
      throw std::logic_error(std::string("command ") + e.name + " sets up as " + commands.back().app->get_name());
  }
  return commands;
}

// A few words on an internal error, without its library's message.
const char* internal_kind(const std::exception& e) {
  if (dynamic_cast<const std::length_error*>(&e)) return "a size beyond what a container holds";
  if (dynamic_cast<const std::out_of_range*>(&e)) return "an index out of range";
  if (dynamic_cast<const std::logic_error*>(&e)) return "a broken assumption";
  return "an unexpected exception";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "sdm: skeleton texture maps (STM) and skeleton displacement maps (SDM).\n"
      "Extracts a curve skeleton from a closed triangle mesh, parameterizes the surface around each\n"
      "skeleton segment as a capsule, packs the rectangles into one square atlas, and uses it to\n"
      "render, encode and transfer textures and displacement."};
  app.require_subcommand(1);
  app.footer("Over folders of models: sdm batch (Python on Dask; sdm batch --help).");
  if (argc > 1 && std::string(argv[1]) == "batch") return sdm::cli::hand_over_to_batch(argc, argv);
  app.set_version_flag("--version", std::string("sdm ") + SDM_VERSION);
#ifdef SDM_FRONT
  // This program has only the light commands; every other command line goes to sdm-full.
  std::vector<std::string> here;
  for (const Entry& e : kCommands) here.push_back(e.name);
  if (!sdm::cli::runs_here(here, argc, argv)) return sdm::cli::hand_over(argv);
#endif
  std::vector<sdm::cli::Command> commands;
  try {
    commands = set_up_commands(app, argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "sdm: failed: " << e.what() << std::endl;
    return 1;
  }
  // An interrupted command leaves no temporary file behind (atomic_file.h).
  sdm::remove_temporaries_on_signal();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  for (auto& c : commands) {
    if (!c.app->parsed()) continue;
    sdm::cli::OutputsBefore outputs;
    try {
      sdm::cli::check_output_paths(*c.app);
      outputs = sdm::cli::record_outputs(*c.app);
      // Every output of the command appears when it returns, together; none when it fails or a signal ends it.
      sdm::OutputCommit commit;
      const int code = c.run();
      commit.commit();
      return code;
    } catch (const sdm::InputError& e) {
      sdm::cli::remove_written_outputs(outputs);  // a failed run leaves none of its outputs
      std::cerr << "sdm " << c.app->get_name() << ": error: " << e.what() << std::endl;
      return 2;
    } catch (const std::bad_alloc&) {
      sdm::cli::remove_written_outputs(outputs);
      std::cerr << "sdm " << c.app->get_name() << ": failed: out of memory (the input needs more than this machine has; "
                << "a smaller input, or a machine with more memory)" << std::endl;
      return 1;
    } catch (const std::runtime_error& e) {
      // The project's own failures (a write that failed, a GL context that could not be made).
      sdm::cli::remove_written_outputs(outputs);
      std::cerr << "sdm " << c.app->get_name() << ": failed: " << e.what() << std::endl;
      return 1;
    } catch (const std::exception& e) {
      // A library's internal error (a JSON type error, a length error, an index out of range): its
      // text names the library's internals, not the input, so the user reads a sentence instead.
      sdm::cli::remove_written_outputs(outputs);
      std::cerr << "sdm " << c.app->get_name() << ": failed: an internal error stopped the command (" << internal_kind(e)
                << "); please report it with the command line and the input" << std::endl;
      return 1;
    } catch (...) {
      sdm::cli::remove_written_outputs(outputs);
      std::cerr << "sdm " << c.app->get_name() << ": failed: an unknown internal error stopped the command" << std::endl;
      return 1;
    }
  }
  return 2;
}
