#pragma once
/// A bounding-volume hierarchy over triangles, for closest-point queries (surface distance) and
/// ray casts (displacement encoding, inside tests). Built once, queried many times; read-only
/// queries are safe from several threads.
#include <Eigen/Dense>
#include <vector>

namespace sdm {

class TriangleBvh {
 public:
  TriangleBvh() = default;
  /// V: points, F: triangles (indices into V). Only the triangles listed in `faces` are used
  /// when it is given (e.g. one segment's faces); hits report indices into F. Leaves hold up to
  /// leaf_size triangles: closest-point queries with wide balls (the medial poles) run faster with
  /// 8, where the triangles' plane bound is cheaper than opening more boxes.
  TriangleBvh(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const std::vector<int>& faces = {},
              int leaf_size = 4);

  struct Closest {
    double distance = INFINITY;
    int face = -1;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
  };
  /// Nearest surface point to p; with max_distance, only points closer than that are looked for
  /// (face == -1 when there is none), which prunes most of the tree for small balls.
  Closest closest_point(const Eigen::Vector3d& p, double max_distance = INFINITY) const;
  /// closest_point(p, max_distance) started from face `hint` (an index into F; -1 or a face not in
  /// the tree: no hint), whose distance bounds the search from the first node: in an iterative
  /// registration the previous step's face is usually the answer or next to it, and less of the
  /// tree is opened. The same faces are searched in the same order, so the same face is found;
  /// `hint` becomes it.
  Closest closest_point_near(const Eigen::Vector3d& p, int& hint, double max_distance = INFINITY) const;
  /// Nearest point to p on the triangles whose unit normal n_f has n_f . n >= min_cos (face == -1
  /// when none does): where two surfaces touch (a raised foot against the other leg), the nearest
  /// point may lie on the sheet facing the other way.
  Closest closest_point_facing(const Eigen::Vector3d& p, const Eigen::Vector3d& n, double min_cos) const;
  /// Nearest point to p on the triangles whose face (index into F) is flagged in `faces` (face == -1
  /// when none is).
  Closest closest_point_among(const Eigen::Vector3d& p, const std::vector<char>& faces) const;

  struct Hit {
    double t = INFINITY;  ///< ray parameter: origin + t * direction
    int face = -1;
    double u = 0, v = 0;  ///< barycentric coordinates of the hit on the face
  };
  /// Nearest hit with t in (t_min, t_max); face == -1 when nothing is hit.
  Hit first_hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t_min = 0,
                double t_max = INFINITY) const;
  /// Number of crossings of the ray with the surface, hits with t > 0 (for parity inside tests).
  int count_hits(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const;
  /// True when some triangle is hit with t in the closed range [t_min, t_max]; stops at the first
  /// one found. any_hit(a, b - a, 0, 1): the closed segment a-b meets the surface.
  bool any_hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t_min, double t_max) const;

  /// Appends to `out` the faces (indices into F) whose bounding boxes meet the box [lo, hi].
  void faces_in_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::vector<int>& out) const;

  bool empty() const { return tris_.empty(); }

 private:
  struct Node {
    /// The box and the links first: the ray queries read only these (64 bytes).
    Eigen::Vector3d lo, hi;
    int left = -1, right = -1;  ///< children, or -1 for a leaf
    int begin = 0, end = 0;     ///< leaf range in tris_
    /// A slab along the node's mean normal that holds its triangles: near the leaves a patch of
    /// surface is nearly flat, so a ball tangent to it (the medial poles' queries) overlaps the
    /// box but not the slab.
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    double slab_lo = 0, slab_hi = 0;
  };
  template <class Accept>
  Closest nearest(const Eigen::Vector3d& p, double max_distance, Accept accept) const;
  /// Walks the leaves whose boxes the ray origin + t direction meets for t in [t_min, t_max()]
  /// (t_max read at every node, so a search can narrow it); `leaf` sees each triangle of a leaf
  /// reached and returns true to end the walk.
  template <class TMax, class Leaf>
  void walk_ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t_min, TMax t_max, Leaf leaf) const;
  /// Lower bound of the squared distance from p to the node's triangles.
  static double node_distance2(const Eigen::Vector3d& p, const Node& n);
  struct Tri {
    /// Unit normal (zero when degenerate): the distance to the plane bounds the distance to the
    /// triangle from below and costs one dot product, against the Voronoi walk's dozen. Beside
    /// a, so that the bound reads one cache line.
    Eigen::Vector3d a, normal, b, c;
    int face;
  };
  /// Builds the subtree over tris_[begin, end) into nodes_[index...] (preorder) and returns one past
  /// its last node; `threads` > 1 builds the two halves at once (the node indices do not depend on it).
  int build(int begin, int end, int index, int threads);
  int leaf_size_ = 4;
  std::vector<Node> nodes_;
  std::vector<Tri> tris_;
  std::vector<int> slot_of_face_;  ///< index into F -> index into tris_, -1 for faces left out
};

/// The ray o + t d meets triangle (a, b, c) at barycentric (u, v), for some t of either sign
/// (Moller & Trumbore 1997, no culling); false when it misses or the ray is parallel to the plane.
bool ray_triangle(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                  const Eigen::Vector3d& c, double& t, double& u, double& v);

/// Closest point on triangle (a, b, c) to p.
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c);

}  // namespace sdm
