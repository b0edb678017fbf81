// sdm compare: how far a mesh lies from a reference mesh.
#include "apps/cli_common.h"
#include "apps/commands.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/surface_distance.h"

#include <iostream>
#include <memory>

namespace sdm::cli {
namespace {

// Compare's summary (its --json object) as text.
void print_compare_text(const nlohmann::json& j) {
  std::cout << j["other"].get<std::string>() << " against " << j["reference"].get<std::string>() << ": RMS "
            << 100 * j["rms"].get<double>() << " %, Hausdorff " << 100 * j["hausdorff"].get<double>() << " % of the diagonal\n";
}

}  // namespace

Command add_compare_command(CLI::App& parent) {
  struct Opts {
    std::string reference, other;
    int samples = 100000;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "compare", "Measure how far a mesh lies from a reference mesh, as 'sdm roundtrip' does: symmetric Hausdorff and\n"
                 "RMS distance by dense sampling (exact closest points), as fractions of the reference's bounding-box\n"
                 "diagonal. For comparing any other tool's output (a Draco decode, a decimation) with sdm's.");
  app->add_option("reference", o->reference, "Reference mesh (.obj, .off, .ply, .stl, .glb, .gltf)")->required();
  app->add_option("other", o->other, "Mesh to measure against it")->required();
  app->add_option("--samples", o->samples, "Points sampled on each surface")->capture_default_str()->check(number_in(1000, 1e7));
  app->add_flag("--json", o->json, "Print one JSON object");
  add_repair_options(app);
  return {app, [o]() {
            const sdm::Mesh a = load_mesh_min_part(o->reference), b = load_mesh_min_part(o->other);
            const sdm::SurfaceDistance d = sdm::surface_distance(a, b, o->samples);
            const double rms = d.rms / d.diagonal, hd = d.hausdorff / d.diagonal;
            // One summary: --json prints it, the text reads it.
            const nlohmann::json j = {{"reference", o->reference}, {"other", o->other}, {"rms", rms}, {"hausdorff", hd},
                                      {"mean", d.mean / d.diagonal}, {"samples", o->samples}};
            if (o->json) print_json(j);
            else print_compare_text(j);
            return 0;
          }};
}

}  // namespace sdm::cli
