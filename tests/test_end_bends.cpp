// Front and back from the ends' bends (libstm/correspondence/end_bends): a stick figure whose feet point
// forward, matched to a copy of itself the right way round and with left and right swapped.
#include "libstm/correspondence/end_bends.h"

#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <array>

namespace {

// Node numbering: 0 pelvis junction, 1 neck junction; per limb its nodes from the junction outwards.
// Left leg 2-4 (hip, knee, ankle) and 5 (toe); right leg 6-8 and 9; left arm 10-12; right arm
// 13-15; head 16-17. `raised` lifts the left thigh forward (hip flexed 90 degrees, shin down).
sdm::Skeleton stick_figure(bool raised = false) {
  sdm::Skeleton s;
  auto leg = [&](double x, bool up) {
    const std::array<Eigen::Vector3d, 4> pts =
        up ? std::array<Eigen::Vector3d, 4>{Eigen::Vector3d(x, -0.1, 0), {x, -0.1, 0.5}, {x, -0.6, 0.5}, {x, -0.6, 0.75}}
           : std::array<Eigen::Vector3d, 4>{Eigen::Vector3d(x, -0.1, 0), {x, -0.6, 0}, {x, -1.1, 0}, {x, -1.1, 0.25}};
    for (const auto& p : pts) s.nodes.push_back(p);
  };
  s.nodes = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 1, 0)};
  leg(0.15, raised);
  leg(-0.15, false);
  for (double x : {0.2, -0.2})
    for (double t : {0.0, 0.4, 0.8}) s.nodes.push_back(Eigen::Vector3d(x + (x > 0 ? t : -t), 1.0, 0));
  s.nodes.push_back(Eigen::Vector3d(0, 1.2, 0));
  s.nodes.push_back(Eigen::Vector3d(0, 1.45, 0.03));
  s.edges = {{0, 1}, {0, 2}, {2, 3}, {3, 4}, {4, 5}, {0, 6}, {6, 7}, {7, 8}, {8, 9}, {1, 10}, {10, 11}, {11, 12},
             {1, 13}, {13, 14}, {14, 15}, {1, 16}, {16, 17}};
  return s;
}

// b's nodes moved as a whole: turned by R, then shifted.
sdm::Skeleton moved(sdm::Skeleton s, const Eigen::Matrix3d& R) {
  for (auto& p : s.nodes) p = R * p + Eigen::Vector3d(3, -1, 2);
  return s;
}

// The same graph with left and right limbs swapped: node k takes the place of its mirror partner.
sdm::Skeleton swapped(const sdm::Skeleton& s) {
  sdm::Skeleton m = s;
  for (int k = 0; k < 4; ++k) std::swap(m.nodes[size_t(2 + k)], m.nodes[size_t(6 + k)]);
  for (int k = 0; k < 3; ++k) std::swap(m.nodes[size_t(10 + k)], m.nodes[size_t(13 + k)]);
  return m;
}

}  // namespace

TEST_CASE("An end's bend is the sine of its angle, across the chain", "[end_bends]") {
  const sdm::Skeleton s = stick_figure();
  // Left foot: the toe segment (0.25 of a 1.35-long chain) turns 90 degrees forward at the ankle.
  const Eigen::Vector3d foot = sdm::end_bend(s.nodes, {5, 4, 3, 2, 0});
  CHECK(foot.norm() == Approx(1.0).margin(0.02));
  CHECK(foot.z() > 0.97);
  // A straight arm does not bend; a chain of no length neither.
  CHECK(sdm::end_bend(s.nodes, {12, 11, 10, 1}).norm() < 1e-12);
  CHECK(sdm::end_bend({Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}, {0, 1}).norm() == 0);
}

TEST_CASE("Ends bend alike on a match the right way round, the other way on a mirror", "[end_bends]") {
  const sdm::Skeleton a = stick_figure();
  for (double turn : {0.0, 90.0, 180.0}) {
    const Eigen::Matrix3d R = Eigen::AngleAxisd(turn * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const sdm::Skeleton b = moved(stick_figure(true), R);
    const double right = sdm::end_bend_agreement(a, b), mirror = sdm::end_bend_agreement(a, swapped(b));
    INFO("turned " << turn << " degrees: right " << right << ", mirror " << mirror);
    // Two feet bent about 90 degrees (a sine near 1 each), the head a little; the mirror turns the
    // core half around, so the feet bend backwards against the target's.
    CHECK(right > 1.8);
    CHECK(mirror < -1.8);
  }
  // Fewer than three ends: no core rotation, no measure.
  sdm::Skeleton chain;
  chain.nodes = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 1, 0)};
  chain.edges = {{0, 1}, {1, 2}};
  CHECK(sdm::end_bend_agreement(chain, chain) == 0);
  CHECK_THROWS(sdm::end_bend_agreement(a, chain));
}
