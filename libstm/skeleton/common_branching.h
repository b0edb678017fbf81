#pragma once
// Tolerance of branch matching to small branches one extraction finds and the other misses (a
// tail, a horn: the extracted skeletons of one shape in two tessellations can differ by such a
// branch). Both skeletons are pruned to a common branching by removing the fewest short end
// branches; among the prunings that make the branchings equal, the one whose match
// (match_skeletons) has the lowest shape cost is chosen. DESIGN 6.
#include "libstm/skeleton/skeleton.h"

#include <vector>

namespace sdm {

struct CommonBranching {
  Skeleton a, b;                      // the pruned skeletons (the given ones when nothing was pruned)
  std::vector<int> a_node, b_node;    // node of the given skeleton -> node of the pruned one (-1: pruned)
  std::vector<int> a_original, b_original;  // node of the pruned skeleton -> node of the given one
  std::vector<int> pruned_a, pruned_b;  // end nodes (of the given skeletons) whose branches were removed
};

// An end branch (the chain from an end node to a junction of degree >= 3) may be removed when its
// length is at most max_branch times the total edge length of its skeleton, and at most
// max_pruned branches are removed in all. The removed nodes' vertices go to the junction the branch
// hung from, so every vertex keeps a node. Skeletons whose branchings are equal come back as they
// are. Throws InputError naming the difference (branching_difference) when no such pruning makes
// the branchings equal and matchable.
CommonBranching common_branching(const Skeleton& a, const Skeleton& b, double max_branch = 0.08, int max_pruned = 2);

}  // namespace sdm
