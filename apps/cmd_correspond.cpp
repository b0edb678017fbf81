// `sdm correspond A B -o C.txt`: the dense correspondence of `sdm transfer` without the texture:
// per vertex of B, the point of A it corresponds to (DESIGN 4.9). No GL context is created.
#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/options.h"
#include "apps/transfer_setup.h"
#include "libstm/core/atomic_file.h"
#include "libstm/core/errors.h"
#include "libstm/core/parallel.h"
#include "libstm/correspondence/correspond.h"
#include "libstm/correspondence/correspondence_file.h"
#include "libstm/correspondence/small_parts.h"
#include "libstm/mesh/mesh.h"
#include "libstm/registration/correspondence_jumps.h"

#include <cmath>
#include <memory>

namespace sdm::cli {

namespace {

struct CorrespondArgs {
  std::string source, target, output, source_skeleton, target_skeleton;
  TransferSettings settings;  // --match, --force, --no-refine
  bool json = false, strict = false;
};

// A model as read and its main parts (small_parts.h; the model itself where its skeleton is given).
struct Model {
  Mesh input;
  MainParts parts;
  const Mesh& mesh() const { return parts.reduced() ? parts.mesh : input; }
};

Model read_model(const std::string& path, const std::string& skeleton, bool strict) {
  Model m;
  m.input = load_mesh_min_part(path);
  if (skeleton.empty()) m.parts = main_parts(m.input, path, strict, progress);
  return m;
}

// x, or null when it is not finite (a stage that was not tried).
nlohmann::json finite_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); }

int run_correspond(const CorrespondArgs& o) {
  if (!has_extension(o.output, {".txt", ".json"})) throw InputError("-o must name a .txt or .json file, not '" + o.output + "'");
  const Model a = read_model(o.source, o.source_skeleton, o.strict), b = read_model(o.target, o.target_skeleton, o.strict);
  Skeleton sa, sb;
  SkeletonStats stats_a, stats_b;
  const Progress shared = serialised(progress);
  auto labelled = [&](const std::string& what) -> Progress {
    return [shared, what](const std::string& line) { shared(line.rfind("extracting", 0) == 0 ? line : what + ": " + line); };
  };
  obtain_both_skeletons(
      a.mesh().n_vertices() + b.mesh().n_vertices(), [&] { sa = skeleton_for(a.mesh(), o.source_skeleton, "source", &stats_a, labelled("source")); },
      [&] { sb = skeleton_for(b.mesh(), o.target_skeleton, "target", &stats_b, labelled("target")); });
  TransferSettings settings = o.settings;
  settings.source_skeleton_given = !o.source_skeleton.empty();
  settings.target_skeleton_given = !o.target_skeleton.empty();
  const CorrespondOptions co = transfer_command_options(settings, a.mesh(), b.mesh(), stats_a, stats_b, progress);
  const Correspondence c = correspond(a.mesh(), sa, b.mesh(), sb, co);
  if (c.points.empty())
    throw InputError("the target was matched by its skeleton alone (its skeleton was given with --target-skeleton, or its genus differs "
                     "from the source's), so no point correspondence was computed. Fix: leave out --target-skeleton");
  const CorrespondenceDiagnostics& d = c.diagnostics;
  if (!d.ambiguity.empty()) progress("warning: left and right (or front and back) may be swapped (--force was given): " + d.ambiguity);
  const CorrespondenceJumps jumps = correspondence_jumps(a.mesh(), b.mesh(), c.points, 0.05 * bounding_box_diagonal(a.mesh()));
  std::vector<SourcePoint> points = a.parts.reduced() ? onto_input_source(a.parts, a.input, c.points) : c.points;
  if (b.parts.reduced()) points = onto_input_target(b.parts, b.input, points);
  write_text_file(o.output, correspondence_text(points, has_extension(o.output, {".json"})));
  // One summary: --json prints it, the text reads it.
  const nlohmann::json j = {{"output", o.output},
                           {"target_vertices", points.size()},
                           {"kind", kind_name(c.kind)},
                           {"fit_rms", finite_or_null(d.fit_rms)},
                           {"fit_p99", finite_or_null(d.fit_p99)},
                           {"registration_rms", finite_or_null(d.registration.rms)},
                           {"refined", d.refined},
                           {"ambiguity", d.ambiguity.empty() ? nlohmann::json() : nlohmann::json(d.ambiguity)},
                           {"attachment", d.attachment},
                           {"distortion", d.distortion},
                           {"rival", d.rival >= 0 ? nlohmann::json(d.rival + 1) : nlohmann::json()},
                           {"final_score", finite_or_null(d.final_score)},
                           {"rival_score", finite_or_null(d.rival_score)},
                           {"rival_kept", d.switched},
                           {"other_source_candidate", d.other_source_candidate},
                           {"other_target_candidate", d.other_target_candidate},
                           {"source_parts_left_out", a.parts.left_out},
                           {"target_parts_left_out", b.parts.left_out},
                           {"jumping_share", jumps.area_share}};
  if (o.json) {
    print_json(j);
  } else {
    const std::string kind = j["kind"];
    const nlohmann::json& fit = j["fit_rms"].is_null() ? j["registration_rms"] : j["fit_rms"];
    std::cout << j["output"].get<std::string>() << ": " << j["target_vertices"] << " target vertices, each with its point of " << o.source
              << "\n  the target "
              << (kind == "carried" ? "is the source's shape: the source's skeleton carried over"
                  : kind == "bent"  ? "is the source in another pose: the source's skeleton bent along"
                                    : "is another body: the source registered onto it along its skeleton")
              << "; fit " << 100 * (fit.is_null() ? NAN : fit.get<double>()) << " % of the diagonal (RMS)"
              << (j["refined"].get<bool>() ? ", refined in the Laplace-Beltrami eigenbases" : "") << "\n";
  }
  return 0;
}

}  // namespace

Command add_correspond_command(CLI::App& parent) {
  auto o = std::make_shared<CorrespondArgs>();
  auto* app = parent.add_subcommand(
      "correspond", "Write the dense correspondence between two models with the same skeleton branching, as 'sdm transfer'\n"
                    "computes it, without a texture or GL: per vertex of TARGET, the face of SOURCE and the barycentric\n"
                    "coordinates of the point it corresponds to (OUT.txt: one line per vertex; OUT.json: two arrays).\n"
                    "Refused (exit code 2, nothing written) as 'sdm transfer' refuses: another branching, a poor fit,\n"
                    "limbs matched to other limbs, or left and right that cannot be told apart, unless --force.");
  app->add_option("source", o->source, "Source mesh (the points the target's vertices take)")->required();
  app->add_option("target", o->target, "Target mesh (one line of the output per vertex)")->required();
  app->add_option("-o,--output", o->output, "Output: .txt (face w0 w1 w2 per target vertex) or .json")->required();
  app->add_option("--source-skeleton", o->source_skeleton, "Source skeleton (.json from 'sdm skeleton') instead of extracting one");
  app->add_option("--target-skeleton", o->target_skeleton, "Target skeleton (.json from 'sdm skeleton') instead of extracting one");
  app->add_option("--match", o->settings.match,
                  "Force a pair of junction or end nodes to correspond: SOURCE_NODE=TARGET_NODE (skeleton node\n"
                  "indices; repeatable)");
  app->add_flag("--no-refine", o->settings.no_refine,
                "Between different bodies, keep the registration's closest points (no ZoomOut refinement)");
  app->add_flag("--force", o->settings.force,
                "Write the correspondence even when the fit is poor, branches disagree, or left and right are a tie");
  app->add_flag("--strict", o->strict,
                "Refuse a model with a small separate part (a blob inside it, a floating speck) instead of leaving the part out\n"
                "of the matching with a warning (its vertices then take the nearest vertex's source point)");
  app->add_flag("--json", o->json, "Print one JSON object instead of text");
  add_repair_options(app);
  return {app, [o]() { return run_correspond(*o); }};
}

}  // namespace sdm::cli
