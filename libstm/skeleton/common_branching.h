#pragma once
/// Tolerance of branch matching to small branches one extraction finds and the other misses (a
/// tail, a horn, a thumb, a heel: the extracted skeletons of one shape, or of two bodies of one
/// kind, differ by such branches) and to junctions split in two (a shoulder found as two degree-3
/// junctions a few millimetres apart in one skeleton, as one degree-4 junction in the other).
/// Both skeletons are reduced to their largest common branching by removing the least significant
/// parts (in the spirit of Au et al. 2008's pruning of short branches, with significance measured
/// by length AND by the share of the model's vertices, i.e. its volume): insignificant end branches
/// are pruned, insignificant chains between two junctions are contracted into one junction. Among
/// the reductions that make the branchings equal, the one with the fewest operations, then the
/// least significance removed, then the lowest match cost (match_skeletons) is chosen. DECISIONS 5, "Common branching".
#include "libstm/skeleton/skeleton.h"

#include <array>
#include <vector>

namespace sdm {

struct CommonBranching {
  Skeleton a, b;                      ///< the reduced skeletons (the given ones when nothing was changed)
  std::vector<int> a_node, b_node;    ///< node of the given skeleton -> node of the reduced one (-1: pruned)
  std::vector<int> a_original, b_original;  ///< node of the reduced skeleton -> node of the given one
                                            ///< (a contracted chain: the junction it was merged into)
  std::vector<int> pruned_a, pruned_b;  ///< end nodes (of the given skeletons) whose branches were removed
  std::vector<std::pair<int, int>> joined_a, joined_b;  ///< junction pairs (given numbering) contracted into one
  /// Branches slid to a neighbouring junction: (the branch's node now joined to it, the junction it
  /// hung from, the junction it hangs from now), given numbering.
  std::vector<std::array<int, 3>> slid_a, slid_b;
  double length_disagreement = 1;  ///< of the match of a and b (length_disagreement); 1 when not measured
};

/// An end branch (the chain from an end node to a junction of degree >= 3) may be removed when its
/// length is at most max_branch times the total edge length of its skeleton AND its nodes own at
/// most max_branch of the skeleton's vertices (a head is short but voluminous: kept). A chain
/// between two distinct junctions may be contracted when it is at most max_branch / 2 of the total
/// length and no other chain joins the same two junctions. At most max_changes operations in all
/// (the least significant candidates are tried, 14 per skeleton at most). The removed nodes'
/// vertices go to the junction the branch hung from (or was merged into), so every vertex keeps a
/// node. Skeletons whose branchings are equal come back as they are.
/// \throw InputError naming the
/// difference (branching_difference) when no such reduction makes the branchings equal and
/// matchable: the major branchings differ.
///
/// When the matched chains of the result disagree in length (length_disagreement above
/// `plausible`: a leg matched to a head), or no pruning works, one branch of either skeleton may
/// also be slid from its junction to a neighbouring one (its part between them, at most 3
/// max_branch of the length, goes; an end branch small enough to prune never slides: a thumb slid
/// along its arm once stood for a head the extraction had lost): extractions of a flat torso hang
/// an arm from the pelvis as often as from the shoulders (the same body written in another format).
/// The plausible result with the fewest changes wins; without one, the first result stands and
/// `length_disagreement` says how poor it is.
CommonBranching common_branching(const Skeleton& a, const Skeleton& b, double max_branch = 0.08, int max_changes = 8,
                                 double plausible = 3.0);

}  // namespace sdm
