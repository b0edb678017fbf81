// common_branching: a short end branch found in one skeleton only is pruned (its vertices go to its
// junction) and the branchings then match; a long limb is never pruned.
#include "libstm/skeleton/common_branching.h"
#include "libstm/core/errors.h"
#include "libstm/skeleton/match_skeletons.h"

#include <catch2/catch.hpp>

namespace {

// A Y: junction at the origin, three arms of `n` edges and length 1 (stem down, arms up left and
// right); optionally a spur of length `spur` along +z from the junction. Ten vertices per node of
// the Y, one per node of the spur (a spur is thin: it owns few of the model's vertices).
sdm::Skeleton y_skeleton(int n, double spur) {
  const Eigen::Vector3d dirs[3] = {{0, -1, 0}, Eigen::Vector3d(-1, 1, 0).normalized(), Eigen::Vector3d(1, 1, 0).normalized()};
  sdm::Skeleton s;
  s.nodes.push_back(Eigen::Vector3d::Zero());
  auto arm = [&](const Eigen::Vector3d& d, double length, int pieces) {
    int prev = 0;
    for (int i = 1; i <= pieces; ++i) {
      s.nodes.push_back(d * length * i / pieces);
      s.edges.push_back({prev, int(s.nodes.size()) - 1});
      prev = int(s.nodes.size()) - 1;
    }
  };
  for (const auto& d : dirs) arm(d, 1.0, n);
  for (size_t i = 0; i < s.nodes.size(); ++i) s.vertex_node.insert(s.vertex_node.end(), 10, int(i));
  if (spur > 0) arm(Eigen::Vector3d::UnitZ(), spur, 2);
  for (size_t i = 3 * n + 1; i < s.nodes.size(); ++i) s.vertex_node.push_back(int(i));
  return s;
}

}  // namespace

TEST_CASE("a short spur on one skeleton is pruned to the common branching", "[common_branching]") {
  const sdm::Skeleton a = y_skeleton(3, 0.2), b = y_skeleton(2, 0);  // spur: 0.2 of 3.2, 6 %
  REQUIRE(!sdm::branching_difference(a, b).empty());
  const sdm::CommonBranching c = sdm::common_branching(a, b);
  CHECK(sdm::branching_difference(c.a, c.b).empty());
  CHECK(c.a.end_nodes() == 3);
  REQUIRE(c.pruned_a.size() == 1);
  CHECK(c.pruned_b.empty());
  CHECK(c.pruned_a[0] == int(a.nodes.size()) - 1);  // the spur's end
  // Two nodes removed (its inner node and its end); their vertices now belong to the junction.
  CHECK(c.a.nodes.size() == a.nodes.size() - 2);
  CHECK(c.a.vertex_node.size() == a.vertex_node.size());
  CHECK(c.a.vertex_node.back() == c.a_node[0]);
  CHECK(c.a_node.back() == -1);
  for (size_t i = 0; i < c.a.nodes.size(); ++i) CHECK((c.a.nodes[i] - a.nodes[c.a_original[i]]).norm() == 0);
  // The other way round: the target's spur goes.
  const sdm::CommonBranching d = sdm::common_branching(b, a);
  CHECK(d.pruned_a.empty());
  CHECK(d.pruned_b.size() == 1);
  // Equal branchings come back unchanged.
  const sdm::CommonBranching e = sdm::common_branching(a, a);
  CHECK(e.pruned_a.empty());
  CHECK(e.a.nodes.size() == a.nodes.size());
}

TEST_CASE("a long fourth limb is not pruned and the mismatch is named", "[common_branching]") {
  // 0.8 of 3.8: 21 % of the skeleton's length, a limb (crossed cylinders against a Y).
  const sdm::Skeleton a = y_skeleton(2, 0), b = y_skeleton(2, 0.8);
  try {
    sdm::common_branching(a, b);
    FAIL("no error");
  } catch (const sdm::InputError& e) {
    const std::string msg = e.what();
    CHECK(msg.find("branchings differ") != std::string::npos);
    CHECK(msg.find("ends 3 vs 4") != std::string::npos);
  }
}
