#pragma once
/// Options and statistics of the curve-skeleton extraction (extract_skeleton.h), in a header of their
/// own so that each stage (surgery.h, refine_skeleton.h, choose_candidate.h) can take them without
/// depending on the whole extraction.
#include "libstm/skeleton/contract_mesh.h"

#include <string>
#include <vector>

namespace sdm {

inline ContractOptions uniform_contraction() {
  ContractOptions o;
  o.cotangent = false;
  o.laplacian_weight = 1.0;
  return o;
}

/// The contraction of a part's isotropic proxy: cotangent weights as Au et al., clamped at
/// 5 (angles above 11 degrees), with the uniform Laplacian added, W_L growing without a practical cap
/// and all 20 iterations run. With the clamp at 1e4 and the cotangents alone, the near-degenerate
/// triangles of the contracting shape got weights in the thousands, the area grew again from the
/// third iteration and the area ratio stalled. Vertices are pinned only once their one-ring has
/// shrunk by 1e11 (was 1e8): pinned earlier, the contracted rim of a torso's sheet held it in place
/// (DESIGN 4.1, BENCHMARKS "Contraction on real meshes").
inline ContractOptions proxy_contraction() {
  ContractOptions o;
  o.cot_max = 5;
  o.uniform_blend = 1;
  o.max_laplacian_growth = 1e8;
  o.stop_when_stagnant = false;
  o.pin_area_ratio = 1e-11;
  return o;
}

/// Where the contracted shape handed to the surgery comes from: Laplacian contraction (Au et al.,
/// the paper's method), the medial poles (medial_poles.h), or both with the better one kept.
enum class SkeletonMethod { automatic, contraction, medial };

/// The method's name as the CLI and the JSON summaries spell it: "auto", "contraction", "medial".
const char* to_string(SkeletonMethod method);

struct SkeletonOptions {
  SkeletonMethod method = SkeletonMethod::automatic;
  ContractOptions contraction = proxy_contraction();  ///< used on the proxy (cotangent weights)
  /// Used on parts contracted as they are: uniform weights with a large start weight, because raw
  /// CAD meshes (long thin triangles) make cotangent weights diverge.
  ContractOptions raw_contraction = uniform_contraction();
  double shape_weight = 1.0;       ///< Au et al.'s w_a (edge quadric: distance to incident edge lines)
  double sampling_weight = 0.1;    ///< Au et al.'s w_b (keeps segment lengths even)
  double min_branch = 0.01;        ///< end branches shorter than this fraction of the diagonal go
  double segment_radius = 1.0;     ///< edges shorter than this multiple of the local radius are merged
  /// End branches shorter than this multiple of their junction's inscribed radius (distance to the
  /// surface) go: they end inside the junction's ball, so they are bumps of its cross-section.
  double prune_radius = 1.0;
  /// The medial-pole candidate wins on tube error only when its error times this is smaller.
  double medial_handicap = 2.0;
  /// Junctions move to the widest inside ball of their cluster when it lies within this many of
  /// its radii (0: off). Two models of one shape then get their junctions in the same place, which
  /// texture transfer needs (transfer_skeleton_options); off by default because at the ypsilon's
  /// junction it leaves one face that assign_faces maps almost flat (L2 stretch 1.15 -> 6.7).
  double centre_junctions = 0.0;
  int medial_smoothing = 4;        ///< umbrella smoothing steps of the poles before their surgery
  /// A part with more vertices than this is contracted through a proxy: the part isotropically
  /// remeshed to about this many vertices (projected onto its surface). Well-shaped triangles keep
  /// the cotangent Laplacian stable and the size bounds the cost.
  /// Smaller parts are contracted as they are (a proxy of their own size lost cycles of the rotor
  /// and anchor in the surgery). 0: never.
  int proxy_max_vertices = 4000;
};

struct SkeletonStats {
  /// Per stage, summed over both candidates (they run on two threads, so the sum can exceed the
  /// wall-clock time in `seconds`).
  double contraction_seconds = 0, surgery_seconds = 0, refinement_seconds = 0;
  double seconds = 0;              ///< wall clock, the whole extraction
  int iterations = 0;              ///< contraction iterations (largest over the parts)
  int parts = 0;
  int refused_collapses = 0;       ///< collapses refused because they would break a cycle of the volume
  int forced_collapses = 0;        ///< taken anyway because nothing else was left
  int proxy_vertices = 0;          ///< total over the parts
  double proxy_seconds = 0;        ///< remeshing and mapping (counted in contraction/refinement too)
  int outside_edges = 0;           ///< edges still crossing the surface after refinement (should be 0)
  int medial_parts = 0;            ///< parts whose skeleton came from the medial poles
  /// The contraction's last area ratio (contracted area over the original; largest over the parts,
  /// -1 when no part was contracted) and, per part, the candidate kept (contraction or medial).
  double area_ratio = -1;
  std::vector<SkeletonMethod> kept;
  double medial_seconds = 0;       ///< computing the poles (summed over the threads that took part)
  int filled_loops = 0;            ///< boundary loops of an open input, closed for the extraction
  int fill_vertices = 0;           ///< vertices the patches added (they map to no output)
  int dropped_nodes = 0;           ///< nodes that owned patch vertices only, merged away
};

}  // namespace sdm
