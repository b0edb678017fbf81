// Branch matching: isomorphism of junctions, ends and chains, with ties broken by geometry.
#include "libstm/core/errors.h"
#include "libstm/skeleton/match_skeletons.h"

#include <catch2/catch.hpp>
#include <random>

using namespace sdm;

namespace {

// A star: arms from a junction at the origin along `dirs`, arm k with `nodes[k]` nodes after the
// junction and length `lens[k]`.
Skeleton star(const std::vector<Eigen::Vector3d>& dirs, const std::vector<double>& lens, const std::vector<int>& nodes) {
  Skeleton s;
  s.nodes.push_back(Eigen::Vector3d::Zero());
  for (size_t k = 0; k < dirs.size(); ++k) {
    int prev = 0;
    for (int i = 1; i <= nodes[k]; ++i) {
      s.nodes.push_back(dirs[k].normalized() * lens[k] * i / nodes[k]);
      s.edges.push_back({prev, int(s.nodes.size()) - 1});
      prev = int(s.nodes.size()) - 1;
    }
  }
  return s;
}

// The same skeleton moved rigidly, scaled, with its nodes renumbered by a permutation.
Skeleton transformed(const Skeleton& s, const Eigen::Matrix3d& R, double scale, unsigned seed, std::vector<int>& new_index) {
  std::vector<int> perm(s.nodes.size());
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(seed));
  new_index = perm;  // old node i -> new node perm[i]
  Skeleton t;
  t.nodes.resize(s.nodes.size());
  for (size_t i = 0; i < s.nodes.size(); ++i) t.nodes[perm[i]] = scale * (R * s.nodes[i]) + Eigen::Vector3d(3, -1, 2);
  for (auto e : s.edges) t.edges.push_back({perm[e[1]], perm[e[0]]});
  std::reverse(t.edges.begin(), t.edges.end());
  return t;
}

int end_node(const ReducedSkeleton& r, int key) { return r.keys[key]; }

}  // namespace

TEST_CASE("A Y matches its moved and renumbered copy arm by arm", "[match_skeletons]") {
  const Skeleton a = star({{0, 1, 0}, {-1, -0.6, 0}, {1, -0.5, 0.2}}, {3.0, 2.0, 1.5}, {4, 3, 2});
  std::vector<int> idx;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Skeleton b = transformed(a, R, 0.5, 7, idx);
  const SkeletonMatch m = match_skeletons(a, b);
  REQUIRE(m.key_a_to_b.size() == 4);
  for (size_t k = 0; k < m.key_a_to_b.size(); ++k)
    CHECK(end_node(m.b, m.key_a_to_b[k]) == idx[end_node(m.a, int(k))]);
  CHECK(m.cost < 1e-9);
  CHECK((m.rotation - R).norm() < 1e-6);
  for (size_t c = 0; c < m.chain_a_to_b.size(); ++c)
    CHECK(m.a.chains[c].edges.size() == m.b.chains[m.chain_a_to_b[c].first].edges.size());
}

TEST_CASE("A symmetric cross is matched by pose, not by node order", "[match_skeletons]") {
  // Four equal arms: every permutation is an isomorphism; only geometry can pick one.
  const Skeleton a = star({{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}}, {2, 2, 2, 2}, {3, 3, 3, 3});
  std::vector<int> idx;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Skeleton b = transformed(a, R, 1.0, 11, idx);
  const SkeletonMatch m = match_skeletons(a, b);
  for (size_t k = 0; k < m.key_a_to_b.size(); ++k)
    CHECK(end_node(m.b, m.key_a_to_b[k]) == idx[end_node(m.a, int(k))]);
  CHECK(m.candidates == 24);
  CHECK(m.confidence > 0.5);
}

TEST_CASE("Fixed pairs override the geometric choice", "[match_skeletons]") {
  const Skeleton a = star({{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}}, {2, 2, 2, 2}, {3, 3, 3, 3});
  // End of arm 0 (node 3) must go to the end of arm 2 (node 9): the cross turns by a half turn.
  const SkeletonMatch m = match_skeletons(a, a, {{3, 9}});
  const auto ka = std::find(m.a.keys.begin(), m.a.keys.end(), 3) - m.a.keys.begin();
  CHECK(m.b.keys[m.key_a_to_b[ka]] == 9);
  CHECK_THROWS_AS(match_skeletons(a, a, {{1, 9}}), InputError);  // node 1 is not a junction or end
}

TEST_CASE("A ring matches a ring with another number of nodes", "[match_skeletons]") {
  auto ring = [](int n, double r) {
    Skeleton s;
    for (int i = 0; i < n; ++i) s.nodes.emplace_back(r * std::cos(2 * M_PI * i / n), r * std::sin(2 * M_PI * i / n), 0.1 * std::cos(2 * M_PI * i / n));
    for (int i = 0; i < n; ++i) s.edges.push_back({i, (i + 1) % n});
    return s;
  };
  const SkeletonMatch m = match_skeletons(ring(12, 1.0), ring(20, 2.0));
  CHECK(m.a.keys.size() == 1);
  CHECK(m.a.chains.size() == 1);
  CHECK(m.a.chains[0].from == m.a.chains[0].to);
  CHECK(m.b.chains[0].edges.size() == 20);
}

TEST_CASE("Different branchings are refused with what differs", "[match_skeletons]") {
  const Skeleton y = star({{0, 1, 0}, {-1, -0.6, 0}, {1, -0.5, 0}}, {3, 2, 2}, {3, 3, 3});
  const Skeleton x = star({{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}}, {2, 2, 2, 2}, {3, 3, 3, 3});
  try {
    match_skeletons(y, x);
    FAIL("no error");
  } catch (const InputError& e) {
    const std::string msg = e.what();
    CHECK(msg.find("junction degrees [3] vs [4]") != std::string::npos);
    CHECK(msg.find("ends 3 vs 4") != std::string::npos);
  }
  CHECK(branching_difference(y, y).empty());
}
