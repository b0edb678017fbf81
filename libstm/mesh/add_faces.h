#pragma once
/// Adding many triangles to an OpenMesh mesh at once, with the connectivity OpenMesh's add_face
/// would build adding them one by one in the same order, element for element: the same edge and
/// halfedge numbering, the same next/prev links (boundaries included) and the same outgoing
/// halfedge at every vertex, which decides where each one-ring circulation starts. The rest of the
/// pipeline inherits that order (sums over one-rings, collapse orders, layouts), so a faster build
/// that ordered things otherwise would move measured results; this one does not.
///
/// add_face spends its time finding each side's halfedge by circulating about the vertex
/// (find_halfedge) and in per-call bookkeeping. Here each side's opposite comes from an edge table
/// (a counting sort, edge_table.h), add_face's linking rules (the cases of a new or an existing side
/// before and after each corner, the relinking of a patch, the adjustment of a vertex's outgoing
/// halfedge to a boundary one) run on flat arrays, and OpenMesh's arrays are filled once at the end.
/// tests/test_mesh.cpp compares every array with add_face's on every shared mesh, open and closed,
/// and on shuffled face orders that make add_face relink patches.
#include "libstm/mesh/edge_table.h"
#include "libstm/mesh/mesh.h"

#include <array>
#include <vector>

namespace sdm {

/// Adds `triangles` (corner indices into the mesh's vertices, counter-clockwise) to `mesh`, which
/// holds its vertices and no edges or faces yet. Returns false, leaving the mesh unchanged, when
/// add_face would refuse one of the faces (a complex vertex or edge, a failed patch relinking)
/// or an edge has more than two sides or two sides in one direction; the caller then adds the
/// faces one by one through add_face, which says which face fails.
/// `table`, when given, is the edge table of the same faces (edge_table.h; its vertex numbering
/// may differ, as build_mesh's drops unused points), saving building it again.
bool add_faces(Mesh& mesh, const std::vector<std::array<int, 3>>& triangles, const EdgeTable* table = nullptr);

/// add_faces, else add_face for every face in order (faces add_face refuses are left out, as
/// add_face leaves them out). Returns the number of faces left out.
size_t add_faces_or_each(Mesh& mesh, const std::vector<std::array<int, 3>>& triangles);

}  // namespace sdm
