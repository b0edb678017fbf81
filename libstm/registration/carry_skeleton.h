#pragma once
/// A skeleton carried from one model onto another of the same shape (a new tessellation, moved or
/// scaled): the nodes and edges go through the registration (register_surfaces), and every vertex of
/// the new model takes the node of the source corner under it on the registered source surface.
/// Two tessellations of one shape then have one skeleton, and a texture transferred between them
/// lines up texel for texel (extracting the skeleton again can move junctions by a tenth of the
/// model: DECISIONS 5, transfer). The correspondence and the vertex rule also serve a skeleton
/// bent onto its target (fit_skeleton) and the transfer's coordinates.
#include "libstm/mesh/mesh.h"
#include "libstm/registration/register_surfaces.h"
#include "libstm/skeleton/skeleton.h"

#include <Eigen/Dense>
#include <vector>

namespace sdm {

/// A point of the source surface: a face and barycentric coordinates in it.
struct SourcePoint {
  int face = -1;
  Eigen::Vector3d barycentric = Eigen::Vector3d(1, 0, 0);
};

/// For every point (e.g. the target's vertices), the source point under it: the closest point of
/// the source placed at `placed` (its vertices moved onto the target, same faces), in that face's
/// barycentric coordinates.
/// With `normals` (one unit normal per point), a point whose closest placed face faces away from its
/// normal takes the closest face that does not, when there is one (touching limbs).
std::vector<SourcePoint> source_points_under(const Mesh& source, const std::vector<Eigen::Vector3d>& placed,
                                             const std::vector<Eigen::Vector3d>& points,
                                             const std::vector<Eigen::Vector3d>& normals = {});

/// The source vertex at the corner of q's face with the largest barycentric weight (the first of equals).
int heaviest_corner(const Mesh& source, const SourcePoint& q);

/// q at the source's own vertex positions.
Eigen::Vector3d position_of(const Mesh& source, const SourcePoint& q);

/// The target's vertex_node through a correspondence (`under`, one source point per target vertex):
/// each vertex takes the node of the source corner with the largest barycentric weight. A node left
/// without a vertex takes the target vertex nearest to `nodes[k]` from a node that owns more than
/// one, so every node owns at least one (when the target has as many vertices as nodes).
std::vector<int> vertex_nodes_through(const Mesh& source, const Skeleton& skeleton, const std::vector<SourcePoint>& under,
                                      const Mesh& target, const std::vector<Eigen::Vector3d>& nodes);

/// `skeleton` belongs to `source` (vertex_node has its vertex count); `source_to_target` registers
/// source onto target. The result has the same edges and node count, nodes at source_to_target of
/// the source's, and a vertex_node for target's vertices (vertex_nodes_through the registered
/// source). Deterministic.
/// \throw InputError when vertex_node does not match the source.
Skeleton carry_skeleton(const Mesh& source, const Skeleton& skeleton, const Mesh& target, const Similarity& source_to_target);

}  // namespace sdm
