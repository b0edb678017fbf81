#pragma once
/// Cutting long skeleton edges into several segments (a layout step, DESIGN 4.4): a capsule fits a
/// curved tube better in short pieces, and many small rectangles pack more tightly than a few long
/// ones.
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/skeleton.h"

#include <vector>

namespace sdm {

/// Every edge longer than max_ratio times its radius (segment_geometry of assign_faces) is cut into
/// n = ceil(length / (max_ratio * radius)) equal pieces by n - 1 new nodes. A vertex owned by one
/// of the edge's end nodes moves to a new node when the edge is the nearest of its node's edges and
/// its projection on the edge falls into that node's slice (nearest of the points k / n); a new node
/// then moves to the centre of its vertices when that lies more than 5 % of the radius off the
/// chord, which follows a curved tube and keeps a straight one's axis exact. New nodes that own no
/// vertex are dropped. Old nodes and edges keep their indices and positions: edge e becomes the
/// first piece (from edges[e][0]), the other pieces are appended after the old edges, new nodes
/// after the old nodes. max_ratio <= 0 or an infinite one changes nothing. Deterministic.
/// origin (optional) receives, per edge of the result, the input edge it is a piece of.
/// \throw InputError when the skeleton does not fit the mesh.
Skeleton split_long_segments(const Mesh& mesh, const Skeleton& skeleton, double max_ratio, std::vector<int>* origin = nullptr);

}  // namespace sdm
