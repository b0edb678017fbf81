#pragma once
/// The skeleton texture map layout (the STM, DESIGN 3 and 4.3-4.7): one capsule and one atlas
/// rectangle per skeleton segment. A layout file alone (it holds the skeleton) defines the STM
/// coordinates of every point of the mesh it was made for.
///
/// This header holds the type and the maps its numbers define; the stages that make and use a
/// layout have their own headers: compute_layout.h (making one), assign_layout_faces.h (faces ->
/// segments), layout_json.h (files), atlas_triangles.h (faces in the atlas), stm_coordinates.h
/// (per-halfedge texture coordinates), l2_stretch.h (their stretch).
#include "libstm/geometry/capsule_uv.h"
#include "libstm/skeleton/skeleton.h"

#include <Eigen/Dense>
#include <vector>

namespace sdm {

/// One segment's capsule and rectangle.
///
/// Rectangle conventions (texels; atlas origin at the lower left, like OBJ/GL texture coordinates):
/// the inner rectangle is [x, x + extent_x] x [y, y + extent_y] with its margin around it. Local
/// capsule coordinates (u around the axis in [0, h), v along it in [0, w], capsule_uv.h) land at
///   not rotated: atlas = (x + v, y + u)    (w along atlas x, h along atlas y)
///   rotated:     atlas = (x + u, y + v)
/// and STM coordinates are atlas / size.
struct LayoutSegment {
  int edge = -1;                       ///< skeleton edge index (segment i is edge i)
  int a = -1, b = -1;                  ///< end nodes, oriented (segment_frames.h)
  Eigen::Vector3d axis, e1, e2;        ///< frame
  double radius = 0, cap = 0, length = 0, area = 0;  ///< model units: r, d = pi r / 2, L, surface
  double weight = 1;                   ///< priority weight: scales the rectangle
  int x = 0, y = 0, w = 0, h = 0;      ///< inner rectangle: w texels along the axis, h around it
  bool rotated = false;
  double d = 0;                        ///< cap length in texels
  /// The capsule runs on as a cylinder past node a (b) by this many radii before its cap starts
  /// (where the second pass leaves faces past a joint folded: assign_faces, segments.h); 0 in
  /// layouts written before them.
  double extend_a = 0, extend_b = 0;
  std::vector<int> neighbours_a, neighbours_b;  ///< segments sharing node a, node b
};

struct Layout {
  int size = 0;        ///< the atlas is size x size texels
  int margin = 0;      ///< texels around every rectangle
  double scale = 0;    ///< texels per model unit (before weights)
  double coverage = 0, coverage_inner = 0;  ///< pack_rectangles.h
  Skeleton skeleton;
  std::vector<LayoutSegment> segments;
  /// The face assignment its atlas was made with (assign_faces(Mesh, Layout), the shaders): 2, with
  /// assign_faces' second pass; 1, the first pass alone, for layouts written before it (JSON without
  /// "assignment"), so that an atlas rendered then is still sampled where it was rendered; 3, the
  /// second pass with extended capsules (LayoutSegment::extend_a, extend_b), which older builds refuse.
  int assignment = 2;
};

/// The capsule frame of segment s (its ends moved out along the axis by the extensions).
/// \throw std::out_of_range when s, or its end nodes, are out of range.
CapsuleFrame capsule_frame(const Layout& layout, int s);
/// Local capsule coordinates (u around, v along) -> atlas texels (the conventions above).
Eigen::Vector2d local_to_atlas(const LayoutSegment& seg, double u, double v);
/// The capsule's length along its axis in model units, caps and extensions included: what the
/// rectangle's w stands for.
double capsule_length(const LayoutSegment& seg);

}  // namespace sdm
