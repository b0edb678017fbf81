#pragma once
// The skeleton texture map layout (the STM, DESIGN 3 and 4.3-4.7): one capsule and one atlas
// rectangle per skeleton segment. A layout file alone (it holds the skeleton) defines the STM
// coordinates of every point of the mesh it was made for.
#include "libstm/core/progress.h"
#include "libstm/geometry/capsule_uv.h"
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/skeleton.h"

#include <array>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sdm {

// Rectangle conventions (texels; atlas origin at the lower left, like OBJ/GL texture coordinates):
// the inner rectangle is [x, x + extent_x] x [y, y + extent_y] with its margin around it. Local
// capsule coordinates (u around the axis in [0, h), v along it in [0, w], capsule_uv.h) land at
//   not rotated: atlas = (x + v, y + u)    (w along atlas x, h along atlas y)
//   rotated:     atlas = (x + u, y + v)
// and STM coordinates are atlas / size.
struct LayoutSegment {
  int edge = -1;                       // skeleton edge index (segment i is edge i)
  int a = -1, b = -1;                  // end nodes, oriented (segment_frames.h)
  Eigen::Vector3d axis, e1, e2;        // frame
  double radius = 0, cap = 0, length = 0, area = 0;  // model units: r, d = pi r / 2, L, surface
  double weight = 1;                   // priority weight: scales the rectangle
  int x = 0, y = 0, w = 0, h = 0;      // inner rectangle: w texels along the axis, h around it
  bool rotated = false;
  double d = 0;                        // cap length in texels
  // The capsule runs on as a cylinder past node a (b) by this many radii before its cap starts
  // (where the second pass leaves faces past a joint folded: assign_faces, segments.h); 0 in
  // layouts written before them.
  double extend_a = 0, extend_b = 0;
  std::vector<int> neighbours_a, neighbours_b;  // segments sharing node a, node b
};

struct Layout {
  int size = 0;        // the atlas is size x size texels
  int margin = 0;      // texels around every rectangle
  double scale = 0;    // texels per model unit (before weights)
  double coverage = 0, coverage_inner = 0;  // pack_rectangles.h
  Skeleton skeleton;
  std::vector<LayoutSegment> segments;
  // The face assignment its atlas was made with (assign_faces(Mesh, Layout), the shaders): 2, with
  // assign_faces' second pass; 1, the first pass alone, for layouts written before it (JSON without
  // "assignment"), so that an atlas rendered then is still sampled where it was rendered; 3, the
  // second pass with extended capsules (LayoutSegment::extend_a, extend_b), which older builds refuse.
  int assignment = 2;
};

struct LayoutOptions {
  int size = 1024;
  int margin = 4;
  std::vector<double> weights;  // per edge of the input skeleton (its pieces share it), empty: all 1
  // Edges longer than split_ratio times their radius are cut into pieces first
  // (split_segments.h); 0 keeps the skeleton's edges as they are.
  double split_ratio = 2.0;
  // Rectangles grow into leftover space up to this ratio between their two growth factors
  // (pack_rectangles.h); 1 keeps the uniform texel density exactly.
  double max_anisotropy = 1.25;
  Progress progress;
};

// Long edges cut (options.split_ratio; the layout keeps the cut skeleton), then segments, face
// assignment, frames, rectangle sizes (w = L + (extensions) r + 2d, h = 2 pi r, times the weight)
// and packing. Throws InputError for a skeleton that does not fit the mesh, bad weights, or an
// atlas too small for the rectangles.
Layout compute_layout(const Mesh& mesh, const Skeleton& skeleton, const LayoutOptions& options = {});

// Faces -> segments as the layout's shaders assign them: assign_faces_with_radii (segments.h) with
// the layout's radii (LayoutSegment::radius, segment by segment) and its rule (Layout::assignment).
// `skeleton`: the layout's skeleton with another mesh's vertex map (a base mesh's), the same graph.
std::vector<int> assign_faces(const Mesh& mesh, const Layout& layout);
std::vector<int> assign_faces(const Mesh& mesh, const Layout& layout, const Skeleton& skeleton);

// The capsule frame of segment s (its ends moved out along the axis by the extensions), and its
// local -> atlas texel map.
CapsuleFrame capsule_frame(const Layout& layout, int s);
Eigen::Vector2d local_to_atlas(const LayoutSegment& seg, double u, double v);
// The capsule's length along its axis in model units, caps and extensions included: what the
// rectangle's w stands for.
double capsule_length(const LayoutSegment& seg);

// JSON: {"format": "sdm-layout", "version": 1, "size", "margin", "scale", "coverage",
// "coverage_inner", "assignment" (Layout::assignment; absent: 1), "skeleton": {...}, "segments": [{"edge", "a", "b", "axis", "e1", "e2",
// "radius", "cap", "length", "area", "weight", "rect": [x, y, w, h], "rotated", "d", "extend"
// ([at a, at b] in radii; only with assignment 3, absent: none), "neighbours_a", "neighbours_b"}]}. Reading throws InputError naming what is wrong: besides the
// structure, it checks what compute_layout guarantees (atlas size within kMaxImageSide, rectangles
// inside the atlas in 64-bit arithmetic, orthonormal frames, positive radii and weights, the
// skeleton's checks of check_skeleton_geometry), so a crafted file cannot index out of bounds.
nlohmann::json layout_to_json(const Layout& layout);
Layout layout_from_json(const nlohmann::json& j);
void write_layout_json(const Layout& layout, const std::string& path);
//! Reads a layout written by write_layout_json; `budget` as for read_skeleton_json.
//! \throw InputError naming the file: not a regular file, too large, refused by `budget`, not JSON,
//! not a valid layout.
Layout read_layout_json(const std::string& path, const ReadBudget& budget = {});

// One triangle as drawn into the atlas: texel coordinates of its corners, unwrapped across the
// phi = 0 seam so that it spans less than half its rectangle around the axis (when it can: a
// triangle around a pole keeps its corners' angles). A seam triangle (reaching past either end
// of its rectangle's u range) comes twice: copy 0 as in stm_coordinates, copy 1 shifted by h the
// other way, so both sides of the seam are filled once each copy is clipped to the rectangle.
struct AtlasTriangle {
  int face = -1, segment = -1, copy = 0;
  std::array<Eigen::Vector2d, 3> atlas;   // texels
  std::array<Eigen::Vector2d, 3> local;   // (u, v) in the segment's rectangle, unwrapped
};
std::vector<AtlasTriangle> atlas_triangles(const Mesh& mesh, const Layout& layout, const std::vector<int>& face_segment);

struct StmCoordinates {
  Mesh mesh;                      // copy of the input with per-halfedge STM texcoords in [0, 1]
  std::vector<int> face_segment;  // assign_faces(mesh, layout), or the one given
  int seam_faces = 0;             // faces unwrapped across phi = 0
  double coverage = 0;            // layout.coverage
  double stretch = 0;             // l2_stretch of the result
};
// `face_segment`, when not empty, is used instead of assign_faces (a transfer target takes the
// source's assignment through its correspondence, so both sides of a segment border agree).
StmCoordinates stm_coordinates(const Mesh& mesh, const Layout& layout, const std::vector<int>& face_segment = {});

// Area-weighted L2 stretch (Sander et al. 2001) of a mesh with per-halfedge texcoords, over the
// given faces (all when empty), after scaling the texture domain so that the faces' parameter area
// equals their surface area: sqrt(sum A_f (|dp/ds|^2 + |dp/dt|^2)/2 / sum A_f); 1 is ideal.
double l2_stretch(const Mesh& mesh, const std::vector<int>& faces = {});

}  // namespace sdm
