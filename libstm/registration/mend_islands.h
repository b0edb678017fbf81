#pragma once
/// Islands of a correspondence between a source placed on a target and the target (source_points_under):
/// where parts of the target touch (a raised foot against the other knee), the closest
/// placed source point of a patch of the target may lie on the other part, so that the patch's source
/// points jump away from those of everything around it (the toes of the raised foot took points on the
/// source's other knee, far away along the surface). A correspondence between
/// surfaces is continuous, so such a patch is mended: its points are looked up again on the placed
/// source, among the faces of the skeleton nodes that its surroundings map to and their neighbours.
#include "libstm/mesh/mesh.h"
#include "libstm/registration/carry_skeleton.h"
#include "libstm/skeleton/skeleton.h"

#include <Eigen/Dense>
#include <vector>

namespace sdm {

struct IslandOptions {
  /// An edge of the target tears when the source points of its ends (at the source's own positions)
  /// lie further apart than this fraction of the source's diagonal: neighbouring target vertices
  /// map a few percent apart at most, even between bodies of different shapes.
  double tear = 0.1;
  /// Parts cut off by torn edges with at most this share of the target's vertices are islands; the
  /// part they lie in is the rest.
  double max_share = 0.02;
  /// The faces an island may take: those of the nodes its surroundings map to, and of the nodes up to
  /// this many skeleton edges from them.
  int node_rings = 2;
};

/// Per target vertex, its island (-1: none), and per island the source faces it may take.
struct CorrespondenceIslands {
  std::vector<int> island_of;
  std::vector<std::vector<char>> allowed_faces;  ///< per island, one flag per source face
};

/// `under` has one source point per target vertex; `skeleton` belongs to `source` (vertex_node of
/// its vertex count). Deterministic.
CorrespondenceIslands find_islands(const Mesh& source, const Skeleton& skeleton, const Mesh& target,
                                   const std::vector<SourcePoint>& under, const IslandOptions& options = {});

/// Looks up again the source point of every point whose island (`point_island`, one per point; -1
/// leaves it) is set: the closest point of the source placed at `placed` among the island's faces.
/// `under` (one per point) is updated. Returns how many points changed.
int mend_islands(const Mesh& source, const std::vector<Eigen::Vector3d>& placed, const CorrespondenceIslands& islands,
                 const std::vector<Eigen::Vector3d>& points, const std::vector<int>& point_island, std::vector<SourcePoint>& under);

}  // namespace sdm
