#include "apps/transfer_setup.h"

#include "libstm/core/errors.h"
#include "libstm/core/parallel.h"
#include "libstm/correspondence/share_skeletons.h"

#include <optional>

namespace sdm::cli {

Skeleton skeleton_for(const Mesh& mesh, const std::string& json_path, const std::string& what, SkeletonStats* stats,
                      const Progress& report, const ReadBudget& budget) {
  if (!json_path.empty()) {
    Skeleton s = read_skeleton_json(json_path, budget);
    if (s.vertex_node.size() != mesh.n_vertices())
      throw InputError(what + " skeleton " + json_path + " was made for a mesh with " + std::to_string(s.vertex_node.size()) +
                       " vertices, not " + std::to_string(mesh.n_vertices()));
    return s;
  }
  if (report) report("extracting the " + what + " skeleton");
  return extract_skeleton(mesh, transfer_skeleton_options(), report, stats);
}

void obtain_both_skeletons(size_t vertices, const std::function<void()>& source, const std::function<void()>& target) {
  if (vertices <= 400000) {
    run_concurrently(target, source);
  } else {
    source();
    target();
  }
}

const char* target_skeleton_name(CorrespondenceKind kind, bool given) {
  switch (kind) {
    case CorrespondenceKind::carried: return "carried";
    case CorrespondenceKind::bent: return "bent";
    case CorrespondenceKind::registered: return "registered";
    case CorrespondenceKind::skeleton_only: break;
  }
  return given ? "given" : "extracted";
}

TransferOptions transfer_command_options(const TransferSettings& settings, const Mesh& source, const Mesh& target,
                                         const SkeletonStats& stats_a, const SkeletonStats& stats_b, const Progress& report) {
  TransferOptions to;
  to.size = settings.size;
  to.margin = settings.margin;
  to.fixed = parse_node_pairs(settings.match);
  to.progress = report;
  // A skeleton the user gives is used as given; an extracted one gives way to the source's
  // when the target turns out to be the source's shape (transfer_texture).
  to.carry_same_shape = !settings.target_skeleton_given;
  to.force = settings.force;
  to.refine = !settings.no_refine;
  // An extracted skeleton may give way to its extraction's other candidate when the branchings
  // differ (TransferOptions::other_candidate); a skeleton given as a file is used as given.
  const bool source_given = settings.source_skeleton_given, target_given = settings.target_skeleton_given;
  to.other_candidate = [&source, &target, &stats_a, &stats_b, source_given, target_given,
                        report](bool of_target) -> std::optional<Skeleton> {
    if (of_target ? target_given : source_given) return std::nullopt;
    return other_transfer_candidate(of_target ? target : source, of_target ? stats_b : stats_a, report);
  };
  return to;
}

}  // namespace sdm::cli
