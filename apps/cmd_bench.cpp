// sdm bench: per-stage timings beside the paper's Table I, coverage beside its Table II, SDM
// encode/decode times, and a large real mesh; with --solvers, --transfer, --load, --pipeline,
// --commands or --pose, one other measurement (apps/bench.h names the file of each).
#include "apps/bench.h"
#include "apps/bench_pose.h"
#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/options.h"

#include <memory>

namespace sdm::cli {

Command add_bench_command(CLI::App& parent) {
  auto o = std::make_shared<BenchOptions>();
  auto* app = parent.add_subcommand(
      "bench", "Time every stage on the paper's five test shapes (beside its Table I and Table II), the SDM\n"
               "encoder and decoder (1024 map; levels 3 and 5), and a large real mesh. Fastest of --repeat runs.\n"
               "With --solvers: the contraction with each sparse Cholesky (supernodal, Eigen, and CHOLMOD in a build\n"
               "configured with -DSDM_WITH_CHOLMOD=ON) on the five shapes, Spot and bunny00's contraction proxy, and how far their results differ.");
  app->add_option("--bunny", o->bunny, "Large mesh for the skeleton timing (skipped with a note when missing)")->capture_default_str();
  app->add_option("--spot", o->spot, "Spot mesh for --solvers (skipped with a note when missing)")->capture_default_str();
  app->add_option("--repeat", o->repeat, "Runs per measurement; the fastest is kept")->capture_default_str()->check(number_in(1, 20));
  add_size_option(app, o->size, "Atlas size for packing and composing", 64, 8192);
  app->add_flag("--no-sdm", o->no_sdm, "Skip the SDM encode/decode timings");
  app->add_flag("--no-gl", o->no_gl, "Skip the GL atlas composing timing");
  app->add_flag("--solvers", o->solvers, "Compare the contraction's sparse Cholesky solvers instead (docs/BENCHMARKS.md)");
  app->add_flag("--transfer", o->transfer,
                "Time texture transfer between different bodies instead (FAUST 007 <-> 024, TOSCA gorilla -> man, from --humans),\n"
                "and measure its correspondence error on every ordered pair of FAUST 001, 007, 010 and 024 against their ground truth");
  app->add_option("--humans", o->humans, "Folder of the human meshes for --transfer (skipped with a note when missing)")->capture_default_str();
  app->add_flag("--turned-scaled", o->turned_scaled,
                "With --transfer: measure the FAUST correspondence with each target turned 180 degrees about its vertical axis and scaled by 1.7");
  app->add_flag("--no-refine", o->no_refine, "With --transfer: transfer as 'sdm transfer --no-refine' (no spectral refinement)");
  app->add_option("--load", o->load, "Time the loading stages (read, validate, build) of these meshes instead");
  app->add_option("--pipeline", o->pipeline,
                  "Take these meshes through every stage instead (load, skeleton, layout and encode at --size, decode at level 3)");
  app->add_option("--commands", o->commands,
                  "Run skeleton, stm (--size), encode and decode (level 3) on these meshes as processes instead, each command "
                  "the 'sdm' beside this program (wall and CPU seconds), beside the same stages in one process");
  app->add_option("--pose", o->pose,
                  "Pose SOURCE like TARGET instead (pairs of meshes with the same connectivity, e.g. FAUST 001 007): per node of "
                  "SOURCE's SDM skeleton the Kabsch motion of its vertices, the map decoded and posed, against linear blend skinning");
  app->add_flag("--json", o->json, "Print one JSON object instead of tables");
  return {app, [o]() {
            if (!o->pose.empty()) return run_pose_bench(o->pose, o->size, o->json, machine_line());
            if (!o->pipeline.empty()) return run_pipeline_bench(*o);
            if (!o->commands.empty()) return run_commands_bench(*o);
            return o->solvers ? run_solvers(*o) : o->transfer ? run_transfer_bench(*o) : !o->load.empty() ? run_load_bench(*o) : run_stages(*o);
          }};
}

}  // namespace sdm::cli
