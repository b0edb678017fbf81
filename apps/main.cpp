#include "apps/commands.h"
#include "apps/hand_over.h"
#include "apps/output_paths.h"
#include "libstm/core/atomic_file.h"
#include "libstm/core/errors.h"
#include "libstm/core/version.h"

#include <iostream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  CLI::App app{
      "sdm: skeleton texture maps (STM) and skeleton displacement maps (SDM).\n"
      "Extracts a curve skeleton from a closed triangle mesh, parameterizes the surface around each\n"
      "skeleton segment as a capsule, packs the rectangles into one square atlas, and uses it to\n"
      "render, encode and transfer textures and displacement."};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("sdm ") + SDM_VERSION);
  // Pipeline order: --help lists them so.
  std::vector<sdm::cli::Command> commands = {
      sdm::cli::add_info_command(app),
      sdm::cli::add_convert_command(app),
      sdm::cli::add_remesh_command(app),
      sdm::cli::add_primitive_command(app),
      sdm::cli::add_skeleton_command(app),
      sdm::cli::add_stm_command(app),
#ifndef SDM_FRONT
      sdm::cli::add_remap_command(app),
      sdm::cli::add_render_command(app),
      sdm::cli::add_encode_command(app),
      sdm::cli::add_decode_command(app),
      sdm::cli::add_roundtrip_command(app),
      sdm::cli::add_compare_command(app),
      sdm::cli::add_transfer_command(app),
      sdm::cli::add_bench_command(app),
#endif
  };
#ifdef SDM_FRONT
  // This program has only the light commands; every other command line goes to sdm-full.
  std::vector<std::string> here;
  for (const auto& c : commands) here.push_back(c.app->get_name());
  if (!sdm::cli::runs_here(here, argc, argv)) return sdm::cli::hand_over(argv);
#endif
  // An interrupted write leaves no hidden temporary file behind (atomic_file.h).
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
      return c.run();
    } catch (const sdm::InputError& e) {
      sdm::cli::remove_written_outputs(outputs);  // a failed run leaves none of its outputs
      std::cerr << "sdm " << c.app->get_name() << ": error: " << e.what() << std::endl;
      return 2;
    } catch (const std::exception& e) {
      sdm::cli::remove_written_outputs(outputs);
      std::cerr << "sdm " << c.app->get_name() << ": failed: " << e.what() << std::endl;
      return 1;
    }
  }
  return 2;
}
