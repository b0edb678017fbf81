#include "libstm/transfer/transfer_texture.h"

#include "libstm/registration/carry_skeleton.h"
#include "libstm/registration/mend_islands.h"
#include "libstm/core/errors.h"
#include "libstm/render/render_atlas.h"
#include "libstm/layout/segment_frames.h"
#include "libstm/layout/segments.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/layout/l2_stretch.h"
#include "libstm/layout/stm_coordinates.h"

#include "libstm/core/parallel.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <cstdlib>
#include <sstream>

namespace sdm {

SkeletonOptions transfer_skeleton_options() {
  SkeletonOptions o;
  o.centre_junctions = 1e9;  // wherever in the cluster the widest ball is
  // The medial candidate whenever it is valid (cycles = genus, no more edges outside): error alone
  // never hands the choice back to the contraction, which loses heads that sit low between the
  // shoulders (tr_reg_085, the TOSCA gorilla). Forcing the medial method instead lost the rotor's
  // cycle, which the validity ranks keep.
  o.medial_handicap = 0;
  return o;
}

Skeleton other_transfer_candidate(const Mesh& mesh, const SkeletonStats& stats, const Progress& progress) {
  SkeletonOptions o = transfer_skeleton_options();
  const bool all_medial = !stats.kept.empty() && std::all_of(stats.kept.begin(), stats.kept.end(), [](SkeletonMethod k) { return k == SkeletonMethod::medial; });
  o.method = all_medial ? SkeletonMethod::contraction : SkeletonMethod::medial;
  return extract_skeleton(mesh, o, progress);
}

namespace {

// The source's layout around the shared skeleton a (the chains are resampled already: both
// models must keep the same graph, so the layout splits nothing).
Layout source_layout(const Mesh& source, const Skeleton& shared_a, const TransferOptions& opt) {
  LayoutOptions lo;
  lo.size = opt.size;
  lo.margin = opt.margin;
  lo.split_ratio = 0;
  lo.progress = opt.progress;
  return compute_layout(source, shared_a, lo);
}

// The target's STM coordinates through its source points (layout_a lies around shared_a, the
// source's shared skeleton): each target face is mapped by the source's capsules at its corners'
// source points, with the segment of the source face under its centroid (one segment for the whole
// face, so seams and borders between rectangles unwrap as in the source). The target then shows the
// source's texture wherever the surfaces correspond, however far the fitted nodes are from where
// the target's own shape would put them (capsule coordinates near a cap's pole turn fast: the
// fitted skeleton's own capsules tore the spots at the back of a turned Spot's head).
StmCoordinates coordinates_through_source(const Mesh& source, const Mesh& target, const Skeleton& shared_a, const Layout& layout_a,
                                          const Correspondence& c) {
  const std::vector<int> fa = assign_faces(source, shared_a);
  Mesh under = target;
  for (auto v : target.vertices()) {
    const Eigen::Vector3d p = position_of(source, c.points[size_t(v.idx())]);
    under.set_point(v, Mesh::Point(p.x(), p.y(), p.z()));
  }
  std::vector<int> face_segment;
  for (auto f : target.faces()) face_segment.push_back(fa[size_t(c.face_points[size_t(f.idx())].face)]);
  StmCoordinates sc = stm_coordinates(under, layout_a, face_segment);
  for (auto v : target.vertices()) sc.mesh.set_point(v, target.point(v));
  sc.stretch = l2_stretch(sc.mesh);
  return sc;
}

}  // namespace

Layout carry_layout(const Layout& la, const Mesh& mesh_b, const Skeleton& b, const Eigen::Matrix3d& rotation,
                    const std::vector<Eigen::Matrix3d>& segment_rotation) {
  if (b.nodes.size() != la.skeleton.nodes.size() || b.edges != la.skeleton.edges)
    throw InputError("the target skeleton's graph differs from the source layout's (resample it with share_skeletons first)");
  std::vector<double> radius;  // as compute_layout: the radii assign_faces' second pass rated with
  const std::vector<int> fs = assign_faces(mesh_b, b, &radius);
  const std::vector<SegmentGeometry> geo = segment_geometry(mesh_b, b, fs, &radius);
  Layout L = la;
  L.skeleton = b;
  for (size_t s = 0; s < L.segments.size(); ++s) {
    LayoutSegment& g = L.segments[s];
    const Eigen::Matrix3d& R = segment_rotation.size() == L.segments.size() ? segment_rotation[s] : rotation;
    const Eigen::Vector3d axis_a = R * g.axis;
    const Eigen::Vector3d d = b.nodes[g.b] - b.nodes[g.a];
    const Eigen::Vector3d axis = d.norm() > 0 ? Eigen::Vector3d(d.normalized()) : axis_a;
    g.e1 = transport_direction(R * g.e1, axis_a, axis);
    g.axis = axis;
    g.e2 = axis.cross(g.e1);
    g.radius = geo[s].radius, g.cap = geo[s].cap, g.length = geo[s].length, g.area = geo[s].area;
  }
  return L;
}

TextureTransfer transfer_texture(GlContext& gl, const Mesh& source, const Image& texture, const Skeleton& skeleton_a,
                                 const Mesh& target, const Skeleton& skeleton_b, const TransferOptions& opt) {
  if (!source.has_halfedge_texcoords2D()) throw InputError("the source has no texture coordinates, so its texture cannot be transferred");
  Correspondence c = correspond(source, skeleton_a, target, skeleton_b, opt);
  TextureTransfer r;
  static_cast<CorrespondenceDiagnostics&>(r) = std::move(c.diagnostics);
  r.kind = c.kind;
  r.skeletons = std::move(c.skeletons);
  r.layout_a = source_layout(source, r.skeletons.a, opt);
  r.layout_b = carry_layout(r.layout_a, target, r.skeletons.b, r.skeletons.rotation, c.segment_rotation);
  report_progress(opt.progress, "remapping the source texture into its STM atlas");
  AtlasOptions ao;
  ao.progress = opt.progress;
  r.atlas = render_atlas(gl, source, r.layout_a, texture, ao);
  report_progress(opt.progress, "target STM coordinates");
  StmCoordinates sc = c.points.empty() ? stm_coordinates(target, r.layout_b)
                                       : coordinates_through_source(source, target, r.skeletons.a, r.layout_a, c);
  r.correspondence = std::move(c.points);
  r.target = std::move(sc.mesh);
  r.stretch = sc.stretch;
  r.seam_faces = sc.seam_faces;
  return r;
}

}  // namespace sdm
