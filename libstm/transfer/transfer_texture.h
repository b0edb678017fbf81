#pragma once
// Texture transfer between two models with the same skeleton branching (paper 1 and 5, DESIGN
// 4.9): the skeletons' branches are matched, matched chains are resampled to the same number of
// segments so both skeletons share one graph (share_skeletons), the source's layout (its STM) is reused for the
// target with the target's own capsules and frames carried from the source's, and the source's
// texture, remapped into its STM atlas, textures the target through the target's STM coordinates.
#include "libstm/core/progress.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/registration/carry_skeleton.h"
#include "libstm/registration/fit_skeleton.h"
#include "libstm/render/gl_context.h"
#include "libstm/core/image.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"
#include "libstm/registration/register_surfaces.h"
#include "libstm/registration/zoomout.h"
#include "libstm/transfer/register_bodies.h"
#include "libstm/transfer/share_skeletons.h"
#include "libstm/skeleton/skeleton.h"

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sdm {

// Extraction options for the two models of a transfer: junctions centred at the widest inside
// ball of their cluster (SkeletonOptions::centre_junctions), so that two tessellations of one
// shape get their junctions in the same place (ypsilon onto its remesh: 21-25 dB -> 31-33 dB), and
// the medial-pole candidate preferred whenever it is valid (DESIGN 6).
SkeletonOptions transfer_skeleton_options();

/// The other extraction candidate of `mesh` for a transfer: transfer_skeleton_options() with the
/// method that extract_skeleton (with those options; `stats` are its statistics) did not keep: the
/// contraction where every part kept the medial poles, else the medial poles. DESIGN 6.
Skeleton other_transfer_candidate(const Mesh& mesh, const SkeletonStats& stats, const Progress& progress = nullptr);

/// Which models an "other extraction candidate" names, in words: "source and the target", "source"
/// or "target" (TextureTransfer::other_source_candidate, other_target_candidate).
const char* other_candidates_named(bool source, bool target);

// The target's layout: layout_a's atlas (size, margin, scale, every rectangle x, y, w, h, rotated,
// d, neighbours, segment ends a -> b) around b's skeleton (the same graph as layout_a.skeleton), with
// b's own segment geometry and frames carried from a's: axis_b = (b - a) of b's nodes,
// e1_b = transport_direction(R e1_a, R axis_a, axis_b). b's capsules thus map into a's rectangles.
// `segment_rotation`, when not empty, gives R per segment instead (a limb turned about its own axis
// turns its frames with it, which the minimal rotation between the axes cannot see).
// Throws InputError when the graphs differ or b does not fit mesh_b.
Layout carry_layout(const Layout& layout_a, const Mesh& mesh_b, const Skeleton& b, const Eigen::Matrix3d& rotation,
                    const std::vector<Eigen::Matrix3d>& segment_rotation = {});

struct TransferOptions {
  int size = 2048;            // atlas texels per side
  int margin = 8;             // texels around every rectangle
  double split_ratio = 2.0;   // share_skeletons
  std::vector<std::pair<int, int>> fixed;  // (source node, target node) key pairs that must match
  // A target that is the source's shape (registered by register_surfaces with an RMS distance under
  // same_shape_rms and a 99th percentile under same_shape_p99, fractions of its diagonal; or under
  // twice that RMS and no more than 1.5 times the bent fit's below) takes the source's skeleton
  // carried over (carry_skeleton) instead of skeleton_b: two extractions of one shape differ with
  // the tessellation, in node positions and even in small branches. Not done when `fixed` pairs
  // are given (they name nodes of skeleton_b).
  bool carry_same_shape = true;
  double same_shape_rms = 0.005, same_shape_p99 = 0.02;
  // Otherwise (same condition) the source's skeleton is bent onto the target (fit_skeleton): it is
  // used when the bent source lies within fit_rms (RMS) and fit_p99 (99th percentile) of the target
  // and no two ends came closer than fit_spread of their distance, unless the registration as another
  // body below fits closer and would be taken (FAUST 024 and 085, two people: bent 0.36-0.38 %, a
  // raised leg folded at the knee; registered 0.29-0.30 %). Measured: a turned head, thicker
  // legs, a bent arm 0.18-0.23 % RMS and 0.8-1.0 %; crossed cylinders bent onto a ypsilon 0.74 %
  // and 2.4 %. Both meshes must have the same Euler characteristic (genus) for either.
  double fit_rms = 0.004, fit_p99 = 0.016, fit_spread = 0.5;
  // Otherwise, a target of another body with the same branching (another person or pose, an animal
  // of the same kind) is registered: the source bent onto it along its skeleton from each of
  // `candidates` matches of the extracted skeletons (register_bodies).
  // A fit worse than registered_rms (RMS) or registered_p99 (99th percentile), fractions of the
  // target's diagonal, is refused unless `force`. Measured on FAUST bodies: 0.1-0.4 % RMS.
  bool register_bodies = true;
  int candidates = 4;
  double registered_rms = 0.01, registered_p99 = 0.04;
  // A match whose branches disagree in relative length by more than this factor
  // (length_disagreement) is refused unless `force`: the surfaces then fit closely while the
  // texture lands on other parts (FAUST 007 -> 085, whose extracted skeleton lacks the head: 25.9;
  // right matches 1.2-2.0).
  double registered_disagreement = 3.0;
  // A match whose end branches meet the core (a torso) at places further apart on the two models
  // than this fraction of the target's diagonal (BodyRegistration::attachment, after the best
  // similarity) is refused unless `force`: limbs are paired with other limbs, which the non-rigid
  // fit then bends into place (the TOSCA man onto FAUST 024: 9.1 %, the final fit 0.48 % RMS, every
  // hand and foot on another; right matches of the five shared bodies 1.1-4.3 %). Not measured (0)
  // where a model's core spans under 3 % of its skeleton (BodyRegistration::attachment).
  double registered_attachment = 0.05;
  // A registration that would be taken but lays the attachments further apart than this is checked
  // against the other extraction candidates (other_candidate) like a refused one, and kept unless
  // another pair fits closer: Homer (alecjacobson/common-3d-test-models), whose medial skeleton
  // joins his right arm to the belly beside the hips, went onto FAUST 007 and back at 4.7 and
  // 4.8 %, upside down; right matches of the five shared bodies lie 1.0-3.5 % apart.
  double marginal_attachment = 0.04;
  // Likewise a registration that would be taken but changes the distances between the extremities
  // by more than this share (BodyRegistration::distortion): a body of other proportions, where a
  // skeleton that hangs a limb from another junction still lays its attachments close. Homer onto
  // FAUST 085 and the TOSCA bodies onto Homer: 0.30-0.47, upside down or scrambled with attachments
  // 2.3-3.6 % apart; the 20 pairs of the five shared bodies 0.03-0.20, so they never pay for it.
  double marginal_distortion = 0.25;
  // When the given skeletons' branchings differ beyond small branches, or their matched branches
  // disagree in length beyond registered_disagreement, so that the target (neither the source's
  // shape nor the source bent) would be refused, each model's other extraction candidate is tried:
  // other_candidate(false) for the source, other_candidate(true) for the target (std::nullopt:
  // none, e.g. a skeleton the user gave). The pairs (a, b'), (a', b), (a', b') are all registered,
  // and of those whose branchings agree (common_branching) and whose branches agree in length (or
  // that would be taken, where the given pair's registration would be refused for another reason
  // or is marginal) the one that fits closest is kept. An extraction keeps one of two
  // candidates, and either can miss a major branch when the coordinates change in their last bits (FAUST
  // tr_reg_085 scaled by 1 + 1e-7: no head end from the medial poles, one from the contraction).
  // Not tried with `fixed` pairs (they name nodes of the given skeletons).
  std::function<std::optional<Skeleton>(bool target)> other_candidate;
  // A registered target's correspondence (closest points of the placed source) refined in the
  // Laplace-Beltrami eigenbases of both models (zoomout; DESIGN 6.5, "Spectral refinement"). Not done
  // for a target carried or bent (the source's shape or pose), where the closest points are right.
  bool refine = true;
  ZoomOutOptions refinement;
  bool force = false;
  Progress progress;
};

struct TextureTransfer {
  SharedSkeletons skeletons;
  Layout layout_a, layout_b;  // the shared STM around each model
  Image atlas;                // the source's texture remapped into layout_a (RGBA, rows top to bottom)
  Mesh target;                // the target with per-halfedge uv into `atlas`
  double stretch = 0;         // l2_stretch of the target's new uv
  int seam_faces = 0;
  Registration registration;  // source onto target (when carry_same_shape was tried)
  bool carried = false;       // the target's skeleton is the source's, carried over
  double fit_rms = INFINITY, fit_p99 = INFINITY;  // the source's skeleton bent onto the target (when tried)
  bool fitted = false;        // the target's skeleton is the source's, bent onto it
  bool registered = false;    // another body: the source registered onto it (fit_rms, fit_p99 its figures)
  // Registered with a model's other extraction candidate (TransferOptions::other_candidate): the
  // node numbers of `skeletons` then refer to that candidate.
  bool other_source_candidate = false, other_target_candidate = false;
  // Registered although another candidate match tied with the chosen one (BodyRegistration::ambiguity,
  // only with `force`): left and right may be swapped.
  std::string ambiguity;
  std::vector<double> candidate_rms;  // per candidate match, the short registration's RMS (registered)
  std::vector<double> candidate_twist, candidate_distortion, candidate_attachment, candidate_bend;  // and BodyRegistration's other measures
  double distortion = 0;              // registered: BodyRegistration::distortion
  double attachment = 0;              // registered: BodyRegistration::attachment
  std::vector<BranchFit> branch_fit;  // registered: per branch
  // Carried, bent or registered: per target vertex, the source point it shows (source face and
  // barycentric coordinates), through which any per-vertex attribute can be carried.
  std::vector<SourcePoint> correspondence;
  bool refined = false;  // registered and refined (TransferOptions::refine)
};

// `source` must have per-halfedge uv for `texture`; skeleton_a/b belong to source/target.
// With options.carry_same_shape the source is first registered onto the target; when the target is
// the source's shape, skeleton_b is replaced by skeleton_a carried over, so a new tessellation of a
// model gets the source's texture texel for texel whatever its own extraction found.
// Throws InputError for a branching mismatch (naming what differs, and how far the target is from
// the source's shape, before any rendering), a source without uv, or skeletons that do not fit
// their meshes.
TextureTransfer transfer_texture(GlContext& gl, const Mesh& source, const Image& texture, const Skeleton& skeleton_a,
                                 const Mesh& target, const Skeleton& skeleton_b, const TransferOptions& options = {});

}  // namespace sdm
