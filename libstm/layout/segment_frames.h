#pragma once
/// Consistent frames for the segments (DESIGN 4.3): one reference direction e1 (phi = 0) per
/// segment, carried along the skeleton by parallel transport so that neighbouring capsules agree
/// and two models with the same branching in a similar pose get corresponding frames.
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/skeleton.h"

#include <vector>

namespace sdm {

struct SegmentFrame {
  int a = -1, b = -1;      ///< the segment's end nodes, oriented by the rule below (may swap the edge's order)
  Eigen::Vector3d axis;    ///< (b - a) / |b - a|
  Eigen::Vector3d e1;      ///< phi = 0, orthogonal to axis
  Eigen::Vector3d e2;      ///< axis x e1
};

/// Frames for every skeleton edge (segment i = edge i). Per connected part of the graph:
///  - root segment: the edge whose end nodes have the least summed eccentricity (graph distances
///    weighted by edge length: the central edge); ties -> more surface (face_segment areas) -> lower
///    index. It points from its more central end (ties: the end owning more surface) to the other.
///  - root e1: principal direction of the part's surface (vertex-area weighted second moment of
///    its points, projected on the plane orthogonal to the root axis), sign chosen so that the
///    third moment along it is positive; when the section is round the area-weighted |x|^2 x
///    moment gives the direction instead.
///  - every other segment: reached by a Dijkstra spanning tree grown from the root segment; e1
///    is carried from node to node by the minimal rotation between consecutive travel directions
///    (the discrete rotation-minimising frame). Segments are oriented along the travel direction on
///    the root's b side and against it on its a side, so that a straight chain is oriented one way.
///    Edges closing a cycle take their frame from their end nearer the root.
/// Depends on geometry and graph only, not on the order of nodes, edges or vertices (up to exact ties).
std::vector<SegmentFrame> segment_frames(const Mesh& mesh, const Skeleton& skeleton, const std::vector<int>& face_segment);

/// The minimal rotation taking unit vector `from` to unit vector `to`, applied to e, then made
/// orthogonal to `to` and unit length. Antiparallel directions keep e (a half turn about e).
Eigen::Vector3d transport_direction(const Eigen::Vector3d& e, const Eigen::Vector3d& from, const Eigen::Vector3d& to);

}  // namespace sdm
