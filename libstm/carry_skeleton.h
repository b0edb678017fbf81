#pragma once
// A skeleton carried from one model onto another of the same shape (a new tessellation, moved or
// scaled): the nodes and edges go through the registration (register_surfaces), and every vertex of
// the new model takes the node of the source vertex nearest to it on the registered source surface.
// Two tessellations of one shape then have one skeleton, and a texture transferred between them
// lines up texel for texel (extracting the skeleton again moves junctions by up to a tenth of the
// model on Spot: DESIGN 6, transfer).
#include "libstm/mesh.h"
#include "libstm/register_surfaces.h"
#include "libstm/skeleton.h"

namespace stm {

// `skeleton` belongs to `source` (vertex_node has its vertex count); `source_to_target` registers
// source onto target. The result has the same edges and node count, nodes at source_to_target of
// the source's, and a vertex_node for target's vertices: the node of the corner nearest to the
// closest point of the registered source surface. A node left without a vertex takes the target
// vertex nearest to it from a node that owns more than one, so every node owns at least one.
// Deterministic. Throws InputError when vertex_node does not match the source.
Skeleton carry_skeleton(const Mesh& source, const Skeleton& skeleton, const Mesh& target, const Similarity& source_to_target);

}  // namespace stm
