#pragma once
/// Disjoint sets with path halving: connected parts of meshes and graphs.
#include <numeric>
#include <vector>

namespace sdm {

class UnionFind {
 public:
  explicit UnionFind(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  /// The representative of x's set.
  int find(int x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  /// Joins the sets of a and b; the representative of b's set represents the union.
  void unite(int a, int b) { parent_[find(a)] = find(b); }
  /// Number of sets.
  int count() {
    int c = 0;
    for (int i = 0; i < int(parent_.size()); ++i) c += find(i) == i;
    return c;
  }

 private:
  std::vector<int> parent_;
};

}  // namespace sdm
