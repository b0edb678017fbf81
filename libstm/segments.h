#pragma once
// Segments of a skeleton (DESIGN 4.3): segment i is skeleton edge i, a -> b, with its capsule.
// Every face of the mesh belongs to exactly one segment.
#include "libstm/mesh.h"
#include "libstm/skeleton.h"

#include <vector>

namespace stm {

// face -> segment (skeleton edge index). Candidates are the segments incident to the nodes of the
// face's vertices. The paper (4) takes the one whose axis is most perpendicular to the face normal;
// here the one whose capsule sees the face most squarely wins: the outward face normal against the
// capsule's radial direction (from the nearest point of the axis segment, so from the end node over
// a cap), the cosine averaged over the corners and the centroid. On a tube that is the paper's rule
// restricted to the segment the face lies over; at junctions it refuses segments that would map
// the face edge-on or folded over. Ties go to the segment nearer the centroid, then to the lower
// index, so the result is deterministic. Normals are made outward per connected part (signed volume).
// Throws InputError when the skeleton has no edge, vertex_node does not match the mesh, or a face
// has no segment in reach.
std::vector<int> assign_faces(const Mesh& mesh, const Skeleton& skeleton);

struct SegmentGeometry {
  double radius = 0;  // area-weighted mean distance of the segment's surface to its axis segment
  double cap = 0;     // cap length d: a quarter of the cap's circumference, pi r / 2
  double length = 0;  // |b - a|
  double area = 0;    // surface area of the segment's faces
};

// Per segment geometry from the faces assigned to it. A segment with no face gets the radius of
// its neighbours' mean (or a tenth of its length when isolated), so that it still has a rectangle.
std::vector<SegmentGeometry> segment_geometry(const Mesh& mesh, const Skeleton& skeleton,
                                              const std::vector<int>& face_segment);

// Distance of p to the segment [a, b]; t receives the unclamped axial parameter.
double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           double* t = nullptr);

}  // namespace stm
