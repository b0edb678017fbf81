// The command line's side of share_skeletons: --match texts parsed into node pairs, and the match
// renumbered into the given skeletons' nodes when common_branching pruned one of them.
#include "libstm/correspondence/share_skeletons.h"
#include "libstm/core/errors.h"

#include <catch2/catch.hpp>

TEST_CASE("node pairs parse from --match texts, in order", "[share_skeletons]") {
  CHECK(sdm::parse_node_pairs({}).empty());
  const auto p = sdm::parse_node_pairs({"3=5", "12=0", " 7=-1"});
  REQUIRE(p.size() == 3);
  CHECK(p[0] == std::make_pair(3, 5));
  CHECK(p[1] == std::make_pair(12, 0));
  CHECK(p[2] == std::make_pair(7, -1));  // whether the node exists is match_skeletons' to say
}

TEST_CASE("a --match text that is not two integers around '=' is refused, naming it", "[share_skeletons]") {
  for (const std::string bad : {"3", "3=", "=5", "a=1", "3=5x", "3 =5", "3=5=6", "99999999999=1"}) {
    INFO(bad);
    try {
      sdm::parse_node_pairs({"1=1", bad});
      FAIL("accepted");
    } catch (const sdm::InputError& e) {
      CHECK(std::string(e.what()) == "--match " + bad + ": expected SOURCE_NODE=TARGET_NODE (two skeleton node indices)");
    }
  }
}

TEST_CASE("the match's keys are renumbered into the given skeletons' nodes", "[share_skeletons]") {
  // A match of pruned skeletons: a's keys are its nodes 0 and 2, b's its nodes 1 and 0; the pruned
  // skeletons' node k was node node_a[k] (node_b[k]) of the given ones.
  sdm::SharedSkeletons s;
  s.match.a.keys = {0, 2};
  s.match.b.keys = {1, 0};
  s.match.key_a_to_b = {1, 0};
  s.match.a.chains.resize(1);
  s.match.a.chains[0].from = 0, s.match.a.chains[0].to = 1, s.match.a.chains[0].nodes = {0, 1, 2};
  s.match.chain_a_to_b = {{0, true}};
  s.match.confidence = 0.75;
  s.node_a = {4, 5, 9};
  s.node_b = {8, 3};
  const sdm::SkeletonMatch m = sdm::match_in_given_numbering(s);
  CHECK(m.a.keys == std::vector<int>{4, 9});
  CHECK(m.b.keys == std::vector<int>{3, 8});
  // Everything else as it was: key and chain correspondences, chains' node lists, measures.
  CHECK(m.key_a_to_b == s.match.key_a_to_b);
  CHECK(m.chain_a_to_b == s.match.chain_a_to_b);
  CHECK(m.a.chains[0].nodes == std::vector<int>{0, 1, 2});
  CHECK(m.confidence == 0.75);
  // Nothing pruned: the numbering is the identity and the match comes back unchanged.
  s.node_a = {0, 1, 2};
  s.node_b = {0, 1};
  const sdm::SkeletonMatch same = sdm::match_in_given_numbering(s);
  CHECK(same.a.keys == s.match.a.keys);
  CHECK(same.b.keys == s.match.b.keys);
}
