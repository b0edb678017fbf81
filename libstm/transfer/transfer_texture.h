#pragma once
// Texture transfer between two models with the same skeleton branching (paper 1 and 5, DESIGN
// 4.9): the skeletons' branches are matched, matched chains are resampled to the same number of
// segments so both skeletons share one graph (share_skeletons), the source's layout (its STM) is reused for the
// target with the target's own capsules and frames carried from the source's, and the source's
// texture, remapped into its STM atlas, textures the target through the target's STM coordinates.
#include "libstm/core/progress.h"
#include "libstm/correspondence/correspond.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/registration/carry_skeleton.h"
#include "libstm/registration/fit_skeleton.h"
#include "libstm/render/gl_context.h"
#include "libstm/core/image.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"
#include "libstm/registration/register_surfaces.h"
#include "libstm/registration/zoomout.h"
#include "libstm/correspondence/register_bodies.h"
#include "libstm/correspondence/share_skeletons.h"
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
// the medial-pole candidate preferred whenever it is valid (DECISIONS 5, "made robust to the extraction").
SkeletonOptions transfer_skeleton_options();

/// The other extraction candidate of `mesh` for a transfer: transfer_skeleton_options() with the
/// method that extract_skeleton (with those options; `stats` are its statistics) did not keep: the
/// contraction where every part kept the medial poles, else the medial poles. DECISIONS 5, "keeps left and right".
Skeleton other_transfer_candidate(const Mesh& mesh, const SkeletonStats& stats, const Progress& progress = nullptr);

// The target's layout: layout_a's atlas (size, margin, scale, every rectangle x, y, w, h, rotated,
// d, neighbours, segment ends a -> b) around b's skeleton (the same graph as layout_a.skeleton), with
// b's own segment geometry and frames carried from a's: axis_b = (b - a) of b's nodes,
// e1_b = transport_direction(R e1_a, R axis_a, axis_b). b's capsules thus map into a's rectangles.
// `segment_rotation`, when not empty, gives R per segment instead (a limb turned about its own axis
// turns its frames with it, which the minimal rotation between the axes cannot see).
// Throws InputError when the graphs differ or b does not fit mesh_b.
Layout carry_layout(const Layout& layout_a, const Mesh& mesh_b, const Skeleton& b, const Eigen::Matrix3d& rotation,
                    const std::vector<Eigen::Matrix3d>& segment_rotation = {});

// The texture transfer's options: the correspondence's (CorrespondOptions) and the atlas's.
struct TransferOptions : CorrespondOptions {
  int size = 2048;  // atlas texels per side
  int margin = 8;   // texels around every rectangle
};

// What the transfer did: the correspondence's diagnostics (CorrespondenceDiagnostics), the shared
// skeletons and layouts, the atlas and the textured target.
struct TextureTransfer : CorrespondenceDiagnostics {
  CorrespondenceKind kind = CorrespondenceKind::skeleton_only;
  SharedSkeletons skeletons;
  Layout layout_a, layout_b;  // the shared STM around each model
  Image atlas;                // the source's texture remapped into layout_a (RGBA, rows top to bottom)
  Mesh target;                // the target with per-halfedge uv into `atlas`
  double stretch = 0;         // l2_stretch of the target's new uv
  int seam_faces = 0;
  bool carried = false;       // the target's skeleton is the source's, carried over
  bool fitted = false;        // the target's skeleton is the source's, bent onto it
  bool registered = false;    // another body: the source registered onto it (fit_rms, fit_p99 its figures)
  // Carried, bent or registered: per target vertex, the source point it shows (source face and
  // barycentric coordinates), through which any per-vertex attribute can be carried.
  std::vector<SourcePoint> correspondence;
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
