#pragma once
/// Whether collapsing a halfedge keeps a triangle mesh a 2-manifold: the link condition (Dey et al.
/// 1999, as OpenMesh's TriConnectivity::is_collapse_ok states it), answered from the halfedge arrays
/// without tagging or allocating. OpenMesh 9's own check builds a vector and looks a property up by
/// name on every call: half of the isotropic remesh's collapse pass, which runs hundreds of thousands
/// of times when a large mesh is remeshed (DECISIONS 6, "The remesh's link condition").
#include "libstm/mesh/mesh.h"

namespace sdm {

/// The answer of mesh.is_collapse_ok(v0v1) (OpenMesh 9.0), for any triangle mesh with vertex, edge
/// and halfedge status: false when the edge or either end is deleted; when a face beside the edge
/// has both of its other sides on the boundary; when the two faces' far corners coincide (or there
/// are no faces); when the ends share a neighbour other than those corners; and when both ends lie
/// on the boundary but the edge does not.
bool collapse_ok(const Mesh& mesh, Mesh::HalfedgeHandle v0v1);

/// Whether collapsing v0v1 would fold a tetrahedron (a closed part of four faces) into two faces on
/// the same three corners, a part with no inside that is no 2-manifold: the link condition lets it
/// through (the ends share exactly the two far corners), so the collapses of the remesh and of the
/// base mesh ask this too. Both ends of a tetrahedron's edge have valence 3 and no boundary, and no
/// other edge's have: a closed vertex of valence 3 has three faces around it, and its neighbour's
/// three faces then close on the fourth.
bool collapses_tetrahedron(const Mesh& mesh, Mesh::HalfedgeHandle v0v1);

}  // namespace sdm
