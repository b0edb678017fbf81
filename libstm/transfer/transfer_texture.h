#pragma once
// Texture transfer between two models with the same skeleton branching (paper 1 and 5, DESIGN
// 4.9): the skeletons' branches are matched, matched chains are resampled to the same number of
// segments so both skeletons share one graph, the source's layout (its STM) is reused for the
// target with the target's own capsules and frames carried from the source's, and the source's
// texture, remapped into its STM atlas, textures the target through the target's STM coordinates.
#include "libstm/core/progress.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/registration/fit_skeleton.h"
#include "libstm/render/gl_context.h"
#include "libstm/core/image.h"
#include "libstm/layout/layout.h"
#include "libstm/skeleton/match_skeletons.h"
#include "libstm/mesh/mesh.h"
#include "libstm/registration/register_surfaces.h"
#include "libstm/skeleton/skeleton.h"

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace sdm {

// Extraction options for the two models of a transfer: junctions centred at the widest inside
// ball of their cluster (SkeletonOptions::centre_junctions), so that two tessellations of one
// shape get their junctions in the same place (ypsilon onto its remesh: 21-25 dB -> 31-33 dB).
SkeletonOptions transfer_skeleton_options();

// Two skeletons resampled onto one graph: a and b have the same node count and the same edge list,
// so edge i of a corresponds to edge i of b, in the same direction. Node k of both is key k of the
// match's reduced a (key_a_to_b[k] in b) for k < keys; then every chain's inner nodes, in order.
struct SharedSkeletons {
  Skeleton a, b;
  SkeletonMatch match;
  std::vector<std::vector<int>> chain_edges;  // per chain of match.a: its edges in the shared graph, in order
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // best rotation of a's shared nodes onto b's
  // common_branching: end nodes of the given skeletons whose short branches were pruned so that the
  // branchings match, and match.a's / match.b's node numbering -> the given skeletons' nodes.
  std::vector<int> pruned_a, pruned_b, node_a, node_b;
};

// Prunes a and b to their common branching (common_branching: at most two end branches, each
// shorter than 8 % of its skeleton, go; `fixed` names nodes of the given skeletons), matches b to a
// (match_skeletons with the `fixed` key node pairs) and resamples every matched pair
// of chains at equal arc-length steps into n segments: n = the larger of the two chains' edge counts,
// raised so that no segment of either model is longer than split_ratio times the chain's mean
// radius (as LayoutOptions::split_ratio; <= 0: no such rule). Key nodes keep their positions.
// A pure cycle (a ring with no junction) has no natural start: b's ring is restarted at the point
// nearest to a's start placed on b by centres and sizes (the same pose assumed), as the ring's turn
// about its axis cannot be told from shape. `rotation` is then fitted to the shared nodes.
// Every vertex is reassigned by projecting it onto the chain of the nearest edge at its old node
// (arc-length position, rounded to the nearest new node); a node left without vertices takes the
// vertex of its chain nearest to it in arc length from a node that has more than one.
// Throws InputError naming the difference when the branchings differ, or when a skeleton does not
// fit its mesh.
SharedSkeletons share_skeletons(const Mesh& mesh_a, const Skeleton& a, const Mesh& mesh_b, const Skeleton& b,
                                const std::vector<std::pair<int, int>>& fixed = {}, double split_ratio = 2.0);

// The target's layout: layout_a's atlas (size, margin, scale, every rectangle x, y, w, h, rotated,
// d, neighbours, segment ends a -> b) around b's skeleton (the same graph as layout_a.skeleton), with
// b's own segment geometry and frames carried from a's: axis_b = (b - a) of b's nodes,
// e1_b = transport_direction(R e1_a, R axis_a, axis_b). b's capsules thus map into a's rectangles.
// `segment_rotation`, when not empty, gives R per segment instead (a limb turned about its own axis
// turns its frames with it, which the minimal rotation between the axes cannot see).
// Throws InputError when the graphs differ or b does not fit mesh_b.
Layout carry_layout(const Layout& layout_a, const Mesh& mesh_b, const Skeleton& b, const Eigen::Matrix3d& rotation,
                    const std::vector<Eigen::Matrix3d>& segment_rotation = {});

// The geometry counterpart (decoding an SDM around another skeleton): `target` matched to `graph`
// (match_skeletons(graph, target, fixed)) and resampled onto graph's own nodes and edges: key nodes
// take the matched target key's position, every inner node of a chain the point of the matched
// target chain at the same arc-length fraction. The result has graph's node count and edge list
// (so decode_sdm's DecodeOptions::skeleton accepts it) and no vertex_node. `match`, when given,
// receives the match. Throws InputError naming the difference when the branchings differ.
Skeleton skeleton_onto_graph(const Skeleton& graph, const Skeleton& target, const std::vector<std::pair<int, int>>& fixed = {},
                             SkeletonMatch* match = nullptr);

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
  // and no two ends came closer than fit_spread of their distance. Measured: a turned head, thicker
  // legs, a bent arm 0.18-0.23 % RMS and 0.8-1.0 %; crossed cylinders bent onto a ypsilon 0.74 %
  // and 2.4 %. Both meshes must have the same Euler characteristic (genus) for either.
  double fit_rms = 0.004, fit_p99 = 0.016, fit_spread = 0.5;
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
