#pragma once
/// Segments of a skeleton (DESIGN 4.3): segment i is skeleton edge i, a -> b, with its capsule.
/// Every face of the mesh belongs to exactly one segment.
#include "libstm/geometry/differential_geometry.h"
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/skeleton.h"

#include <array>
#include <vector>

namespace sdm {

/// face -> segment (skeleton edge index). Candidates are the segments incident to the nodes of the
/// face's vertices (all segments when there are none). The paper (4) takes the one whose axis is
/// most perpendicular to the face normal; here each candidate maps the face with its capsule map,
/// the face's mean distance to the segment as radius, and the L2 stretch of that triangle map
/// decides: candidates with stretch < 2 that do not fold the face win, and among them the one whose
/// radial direction best matches the outward normal (cosine averaged over the corners and the
/// centroid); otherwise the lowest stretch; folded ones last. On a tube that is the paper's rule
/// restricted to the segment the face lies over; at junctions it refuses segments that would map
/// the face edge-on or folded over. Ties go to the segment nearer the centroid, then to the lower
/// index, so the result is deterministic. Normals are made outward per connected part
/// (face_orientation).
/// \throw InputError when the skeleton has no edge, vertex_node does not match
/// the mesh, or a face has no segment in reach.
/// A second pass then looks again at every face that its segment, mapping it with the
/// segment's radius (segment_geometry of the first pass: what the layout's rectangle uses), folds
/// over or stretches by 2 or more: such a face goes to whichever segment at a node within two
/// skeleton edges of its nodes maps it with the least stretch, a folded map counting twice its
/// stretch (ties to the lower index). The first pass rates a candidate with the face's own distance,
/// blind to how far the face lies from the radius its segment's rectangle is made for, and looks at
/// the face's own nodes only: a few faces folded or mapped almost flat held most of the L2 stretch
/// (BENCHMARKS "Layout stretch").
/// Where the second pass still leaves a face past a joint (a node of degree 2 or more) folded over
/// by its segment's cap with a stretch of 2 or more, every segment end at that joint is *extended*:
/// its capsule runs on as a cylinder for kCapExtension radii before the cap starts, and the second
/// pass runs again with those capsules. The paper's cap is a hemisphere about the node;
/// at a bend or where a fat part narrows, the faces around a joint lie beyond both segments' ends and
/// face the node, so every cap folds them, and a cylinder that runs on maps them the right way
/// round. An extension lengthens the rectangle, so only joints with such faces get one (DECISIONS 3:
/// extending every joint costs texels on the paper's shapes, which need none).
/// `extensions_used`, when given, receives the extensions (per edge, in radii at edges[e][0] and
/// edges[e][1]; all 0 when no joint needed one).
/// `radii_used`, when given, receives the radii of the second pass (one per edge); with
/// `second_pass` false the first pass's faces come back alone (its radii need no more).
/// Both passes are mirrored by the geometry shader of render_stm (shaders/stm.geom.glsl).
std::vector<int> assign_faces(const Mesh& mesh, const Skeleton& skeleton, std::vector<double>* radii_used = nullptr,
                              bool second_pass = true, std::vector<std::array<double, 2>>* extensions_used = nullptr);

/// The same rule with the radii of the second pass given (one per skeleton edge, positive): a
/// layout's LayoutSegment::radius (assign_faces(Mesh, Layout) in assign_layout_faces.h), which compute_layout
/// takes from the first pass, so that any mesh is assigned as the layout's own shaders assign it.
/// second_pass false: the first pass alone (the rule of layouts written before the second pass).
/// `extensions` (one per edge, in radii at edges[e][0] and edges[e][1]; empty: none, the rule of
/// layouts written before them) are the capsules' extensions the second pass maps with.
std::vector<int> assign_faces_with_radii(const Mesh& mesh, const Skeleton& skeleton, const std::vector<double>& radii,
                                         bool second_pass = true,
                                         const std::vector<std::array<double, 2>>& extensions = {});

/// The extension an extended end gets, in radii (the shortest of those tried that keeps the 99th
/// percentile of stretch under 4 with a margin: docs/BENCHMARKS.md); and the largest a layout may
/// hold (check_layout).
constexpr double kCapExtension = 1.5;
constexpr double kMaxCapExtension = 4;

/// face -> +1, or -1 when the face's connected part (through shared edges) is wound inside out
/// (negative signed volume): the factor that makes the face's normal outward in assign_faces.
std::vector<int> face_orientation(const Mesh& mesh);

struct SegmentGeometry {
  double radius = 0;  ///< area-weighted mean distance of the segment's surface to its axis segment
  double cap = 0;     ///< cap length d: a quarter of the cap's circumference, pi r / 2
  double length = 0;  ///< |b - a|
  double area = 0;    ///< surface area of the segment's faces
};

/// Per segment geometry from the faces assigned to it. A segment with no face gets the radius of
/// its neighbours' mean (or a tenth of its length when isolated), so that it still has a rectangle.
/// `radius`, when given (one per edge: assign_faces' radii_used), replaces the measured radii and
/// sets the caps from them: the radii a layout's rectangles are made for.
std::vector<SegmentGeometry> segment_geometry(const Mesh& mesh, const Skeleton& skeleton,
                                              const std::vector<int>& face_segment,
                                              const std::vector<double>* radius = nullptr);

}  // namespace sdm
