#pragma once
/// The half-edges of a triangle soup grouped by undirected edge, in the order (smaller vertex,
/// larger vertex): a counting sort on the smaller vertex, then each vertex's few entries sorted.
/// Linear in the faces and one allocation per array; validation (validate_mesh) reads edge use,
/// boundary loops and parts from it, and build_mesh links the halfedge structure from it. The hash
/// maps of vectors it replaced spent most of validation's time in allocation.
#include "libstm/mesh/mesh.h"

#include <array>
#include <vector>

namespace sdm {

struct EdgeTable {
  std::vector<int> lo, hi;      ///< per entry: the edge's vertices, lo < hi
  std::vector<int> halfedge;    ///< per entry: 3 f + c, the face's side from corner c to corner c + 1
  std::vector<char> forward;    ///< per entry: the face runs lo -> hi
  std::vector<size_t> group;    ///< entries of edge e: [group[e], group[e + 1])
  size_t edges() const { return group.empty() ? 0 : group.size() - 1; }
  size_t uses(size_t e) const { return group[e + 1] - group[e]; }
  int face(size_t entry) const { return halfedge[entry] / 3; }
};

/// The table of the faces f with use[f] != 0 (use empty: every face). Corner indices must lie in
/// [0, vertices) and a face's three corners differ (validate_mesh's check_face_indices).
EdgeTable edge_table(const std::vector<std::array<int, 3>>& triangles, size_t vertices, const std::vector<char>& use = {});
inline EdgeTable edge_table(const MeshSoup& soup, const std::vector<char>& use = {}) {
  return edge_table(soup.triangles, soup.points.size(), use);
}

/// The table after faces were dropped from the soup: `index[f]` is face f's number afterwards, -1
/// when dropped, the numbers increasing with f (as keeping faces in order gives them). Equals
/// edge_table of the soup without those faces, at the cost of a copy instead of a sort.
EdgeTable without_faces(const EdgeTable& t, const std::vector<int>& index);

/// Every side without an opposite, as (a, b, face) with the face running a -> b: the rim of an
/// open mesh's holes.
std::vector<std::array<int, 3>> boundary_halfedges(const EdgeTable& t);

}  // namespace sdm
