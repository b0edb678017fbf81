#pragma once
/// The crossing face pairs of crossing_face_pairs (CGAL's count, self_intersections.h) among the
/// pairs whose two faces lie in one group or in two groups marked near each other, searched again as
/// the points move: the decoder's folds, whose two faces come from one base face or from base faces
/// that share a corner (libsdm/decode/untangle_decoded.h). A box tree per group is built once on the
/// first positions and refitted to later ones (only the groups whose faces may have moved), and each
/// pair of near groups is searched tree against tree: no tree over the whole mesh, no search from a
/// root per face, and pairs of far groups are never looked at. The pairs found are those that
/// crossing_face_pairs over the whole mesh finds joining near groups: the same face boxes (closed)
/// pick the pairs to test, and the same test (face_pair_crosses) decides.
#include <Eigen/Dense>

#include <array>
#include <vector>

namespace sdm {

class GroupedCrossings {
 public:
  /// F: triangles (indices into `points`); face_group: each face's group in [0, near.size()); near[g]:
  /// the groups near group g, g itself among them when pairs within g are wanted (the relation must
  /// be symmetric). The trees split each group's faces at their centres at `points`.
  GroupedCrossings(const Eigen::MatrixX3i& F, const std::vector<int>& face_group, std::vector<std::vector<int>> near,
                   const std::vector<Eigen::Vector3d>& points);

  /// The crossing pairs (f, g), f < g, sorted, at `points`. `faces`, when given (one flag a face),
  /// restricts them to pairs with a flagged face and says which faces may have moved since the last
  /// call: the corners of the others must be where they were then (the first call takes every face).
  std::vector<std::array<int, 2>> find(const std::vector<Eigen::Vector3d>& points, const std::vector<char>& faces = {});

 private:
  struct Node {
    Eigen::Vector3f lo, hi;  ///< float, rounded outwards: half the memory the search walks
    int right = -1;          ///< the second child (the first follows the node); -1 for a leaf
    int begin = 0, end = 0;  ///< the node's faces: a range of order_
  };
  int build(int begin, int end, int index, const std::vector<Eigen::Vector3d>& centre);
  void refit(int group, const std::vector<Eigen::Vector3d>& points, const std::vector<char>& faces);
  void search(int g, int h, const std::vector<Eigen::Vector3d>& points, const std::vector<char>& faces, const std::vector<char>& look,
              std::vector<std::array<int, 2>>& out) const;

  std::vector<std::vector<int>> near_;
  std::vector<int> order_;                  ///< the faces by group, each group in its tree's order
  std::vector<int> group_start_;            ///< group g's faces: order_[group_start_[g], group_start_[g + 1])
  std::vector<int> root_;                   ///< each group's root node (-1: no face)
  std::vector<Node> nodes_;                 ///< each group's nodes together, the root first
  std::vector<std::array<int, 3>> corner_;  ///< per slot of order_: the face's corners
  std::vector<Eigen::Vector3d> lo_, hi_;    ///< per slot of order_: the face's box
  std::vector<char> flagged_;               ///< per node: a flagged face below it (find with `faces`)
  bool first_ = true;
};

}  // namespace sdm
