#pragma once
/// Extractions often split the junction where the two limbs of a pair meet (a body's shoulders: two
/// degree-3 junctions a few percent of the skeleton's length apart, one arm at each), and which limb
/// hangs from which of the two follows the last bits of the coordinates (every coordinate moved by
/// 1e-7 of the diagonal: either arm). Two skeletons split the other way round match only
/// with the pair crossed, the left arm of one on the right arm of the other: the split, not the
/// shape, then decides left and right, and no candidate match has them right. The variants here
/// exchange such a pair between its two junctions, so that the matcher offers both assignments and
/// the registration chooses between them (register_bodies). DECISIONS 5, "keeps left and right".
#include "libstm/skeleton/skeleton.h"

#include <vector>

namespace sdm {

/// Variants of `s`, one per set of exchanges on disjoint junction pairs. An exchange: two junctions
/// (degree >= 3) joined by a chain of at most `max_inner` times the skeleton's total edge length,
/// with an end branch at each whose lengths differ by at most the factor `max_ratio`; the two
/// branches' first edges swap junctions. Nodes, vertex_node and every degree stay as they are.
/// Empty when no pair qualifies; at most 63 variants (the first six exchanges). Deterministic.
std::vector<Skeleton> exchanged_branches(const Skeleton& s, double max_inner = 0.04, double max_ratio = 1.25);

}  // namespace sdm
