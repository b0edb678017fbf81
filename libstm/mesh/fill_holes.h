#pragma once
/// Closing the holes of an open mesh: scans and cut models have boundary loops, and the
/// skeleton's contraction and inside tests need a surface that bounds a volume. Each loop gets a
/// patch of concentric rings of triangles with edges about as long as the loop's own, whose inner
/// vertices are then placed by a membrane fairing (uniform Laplacian = 0, the loop held; Liepa 2003,
/// "Filling holes in meshes", triangulate-refine-fair, with rings instead of the minimum-weight
/// triangulation: linear in the loop's size and never folded over in the patch's own parameter
/// domain). The original vertices and faces come first, unchanged, so a map computed on the filled
/// mesh (a skeleton's vertex->node map) restricts to the input by truncation.
#include "libstm/mesh/mesh.h"

#include <Eigen/Dense>

namespace sdm {

struct FilledMesh {
  Eigen::MatrixX3d V;       ///< the input's vertices, then the patches' inner vertices
  Eigen::MatrixX3i F;       ///< the input's faces, then the patches' faces (oriented like the input)
  int original_vertices = 0, original_faces = 0;
  int loops = 0;            ///< boundary loops closed
};

/// Boundary loops of an oriented 2-manifold triangle mesh (F over V's rows), each as the vertex
/// sequence along the hole: consecutive vertices a, b form an edge the faces use only as b -> a.
std::vector<std::vector<int>> boundary_loops(const Eigen::MatrixX3i& F, int vertices);

/// Closes every boundary loop. A loop of n vertices gets about n / (2 pi) rings (at most
/// kMaxFillRings, so a patch adds at most ~kMaxFillRings * n / 2 vertices), each ring with
/// proportionally fewer vertices, and one centre vertex. A closed mesh comes back unchanged.
constexpr int kMaxFillRings = 24;
FilledMesh fill_holes(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

/// The same for a halfedge mesh: the closed result (`--fill-holes`), input vertices first.
Mesh fill_holes(const Mesh& mesh);

}  // namespace sdm
