#pragma once
/// Texture transfer between two models with the same skeleton branching (paper 1 and 5, DESIGN
/// 4.9): the dense correspondence (correspond: the target is the source's shape, carried; the
/// source in another pose, bent; or another body, registered; the skeletons resampled onto one
/// graph) gives per target vertex the source point it shows. The source's layout (its STM around
/// the shared skeleton) is carried to the target (carry_layout), the source's texture is remapped
/// into that atlas, and the target takes its STM coordinates through its source points (matched by
/// the skeletons alone: its own coordinates in the carried layout).
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

/// Extraction options for the two models of a transfer: junctions centred at the widest inside
/// ball of their cluster (SkeletonOptions::centre_junctions), so that two tessellations of one
/// shape get their junctions in the same place, and the medial-pole candidate preferred whenever
/// it is valid (DECISIONS 5, "made robust to the extraction").
SkeletonOptions transfer_skeleton_options();

/// The other extraction candidate of `mesh` for a transfer: transfer_skeleton_options() with the
/// method that extract_skeleton (with those options; `stats` are its statistics) did not keep: the
/// contraction where every part kept the medial poles, else the medial poles. DECISIONS 5, "keeps
/// left and right". \throw whatever extract_skeleton throws (InputError for a mesh it cannot take).
Skeleton other_transfer_candidate(const Mesh& mesh, const SkeletonStats& stats, const Progress& progress = nullptr);

/// The target's layout: layout_a's atlas (size, margin, scale, every rectangle x, y, w, h, rotated,
/// d, neighbours, segment ends a -> b) around b's skeleton (the same graph as layout_a.skeleton), with
/// b's own segment geometry and frames carried from a's: axis_b = (b - a) of b's nodes,
/// e1_b = transport_direction(R e1_a, R axis_a, axis_b). b's capsules thus map into a's rectangles.
/// `segment_rotation`, when not empty, gives R per segment instead (a limb turned about its own axis
/// turns its frames with it, which the minimal rotation between the axes cannot see).
/// \pre b has layout_a.skeleton's nodes and edges (share_skeletons) and a node for every vertex of mesh_b.
/// \throw InputError when the graphs differ or b does not fit mesh_b.
Layout carry_layout(const Layout& layout_a, const Mesh& mesh_b, const Skeleton& b, const Eigen::Matrix3d& rotation,
                    const std::vector<Eigen::Matrix3d>& segment_rotation = {});

/// The texture transfer's options: the correspondence's (CorrespondOptions) and the atlas's.
struct TransferOptions : CorrespondOptions {
  int size = 2048;  // atlas texels per side
  int margin = 8;   // texels around every rectangle
};

/// What the transfer did: the correspondence's diagnostics (CorrespondenceDiagnostics), what the
/// target was found to be, the shared skeletons and layouts, the atlas and the textured target.
struct TextureTransfer : CorrespondenceDiagnostics {
  /// carried: the target's skeleton is the source's, carried over; bent: the source's, bent onto
  /// it; registered: another body, the source registered onto it (fit_rms, fit_p99 its figures).
  CorrespondenceKind kind = CorrespondenceKind::skeleton_only;
  SharedSkeletons skeletons;
  Layout layout_a, layout_b;  // the shared STM around each model
  Image atlas;                // the source's texture remapped into layout_a (RGBA, rows top to bottom)
  Mesh target;                // the target with per-halfedge uv into `atlas`
  double stretch = 0;         // l2_stretch of the target's new uv
  int seam_faces = 0;
  /// Carried, bent or registered: per target vertex, the source point it shows (source face and
  /// barycentric coordinates), through which any per-vertex attribute can be carried.
  std::vector<SourcePoint> correspondence;
};

/// The source's texture on the target, through correspond(source, skeleton_a, target, skeleton_b).
/// With options.carry_same_shape the source is first registered onto the target; when the target is
/// the source's shape, skeleton_b is replaced by skeleton_a carried over, so a new tessellation of a
/// model gets the source's texture texel for texel whatever its own extraction found.
/// \pre `source` has per-halfedge uv for `texture`; skeleton_a and skeleton_b belong to source and
/// target (a node for every vertex).
/// \throw InputError for a branching mismatch (naming what differs, and how far the target is from
/// the source's shape, before any rendering), a correspondence the acceptance judge refuses
/// (judge_correspondence), a source without uv, or skeletons that do not fit their meshes.
TextureTransfer transfer_texture(GlContext& gl, const Mesh& source, const Image& texture, const Skeleton& skeleton_a,
                                 const Mesh& target, const Skeleton& skeleton_b, const TransferOptions& options = {});

}  // namespace sdm
