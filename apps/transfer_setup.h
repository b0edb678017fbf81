#pragma once
// What `sdm transfer` and `sdm bench --transfer` share, so that the bench measures the command as
// a user runs it: how each model's skeleton is obtained, the two at once, and the TransferOptions
// the command hands transfer_texture.
#include "libstm/core/progress.h"
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/skeleton/skeleton.h"
#include "libstm/transfer/transfer_texture.h"

#include <functional>
#include <string>
#include <vector>

namespace sdm::cli {

/// The skeleton read from json_path (it must map mesh's vertices), or else extracted with the
/// transfer's options (transfer_skeleton_options; its statistics into *stats); `what` names the
/// model in messages; the file is read within `budget` (json_budget). Throws InputError for a
/// skeleton file made for another vertex count.
Skeleton skeleton_for(const Mesh& mesh, const std::string& json_path, const std::string& what, SkeletonStats* stats,
                      const Progress& report, const ReadBudget& budget = {});

/// Runs `source` and `target` (each obtains one model's skeleton) on two threads when the two
/// models have at most 400000 vertices together, else one after the other (their extractions'
/// memory would add up). An extraction keeps a second core busy only while its medial candidate
/// runs (docs/BENCHMARKS.md, "Thresholds: what they rest on"). Rethrows what either threw.
void obtain_both_skeletons(size_t vertices, const std::function<void()>& source, const std::function<void()>& target);

/// The options of `sdm transfer` a user can set that reach transfer_texture, with the command's defaults.
struct TransferSettings {
  int size = 2048, margin = 8;
  std::vector<std::string> match;  // --match SOURCE_NODE=TARGET_NODE
  bool force = false;
  bool no_refine = false;  // --no-refine
  bool source_skeleton_given = false, target_skeleton_given = false;  // --source-skeleton, --target-skeleton
};

/// How the transfer found the target's skeleton, as `sdm transfer --json` names it
/// ("target_skeleton"): the correspondence's kind ("carried", "bent", "registered"), else
/// "given" (--target-skeleton) or "extracted".
const char* target_skeleton_name(CorrespondenceKind kind, bool given);

/// The TransferOptions `sdm transfer` runs transfer_texture with: atlas size and margin, the
/// --match pairs, the source's skeleton carried over only onto a target whose skeleton was
/// extracted, --force, and each model's other extraction candidate (other_transfer_candidate from
/// `stats_a`, `stats_b`) where its skeleton was extracted. `source`, `target` and the statistics
/// are referred to, not copied: they must outlive the options. Throws InputError for a malformed
/// --match pair.
TransferOptions transfer_command_options(const TransferSettings& settings, const Mesh& source, const Mesh& target,
                                         const SkeletonStats& stats_a, const SkeletonStats& stats_b, const Progress& report);

}  // namespace sdm::cli
