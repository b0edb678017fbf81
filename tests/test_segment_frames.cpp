#include "libstm/layout/segment_frames.h"
#include "libstm/layout/segments.h"
#include "synthetic_shapes.h"

#include <catch2/catch.hpp>
#include <cmath>

using Eigen::Vector3d;

namespace {

std::vector<sdm::SegmentFrame> frames_of(const synth::Shape& s) {
  return sdm::segment_frames(s.mesh, s.skeleton, sdm::assign_faces(s.mesh, s.skeleton));
}

double angle_deg(const Vector3d& a, const Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / M_PI;
}

void check_orthonormal(const std::vector<sdm::SegmentFrame>& f, const sdm::Skeleton& sk) {
  for (size_t s = 0; s < f.size(); ++s) {
    const auto& e = sk.edges[s];
    CHECK(((f[s].a == e[0] && f[s].b == e[1]) || (f[s].a == e[1] && f[s].b == e[0])));
    CHECK(f[s].axis.isApprox((sk.nodes[f[s].b] - sk.nodes[f[s].a]).normalized(), 1e-12));
    CHECK(f[s].e1.norm() == Approx(1).epsilon(1e-12));
    CHECK(std::abs(f[s].e1.dot(f[s].axis)) < 1e-12);
    CHECK(f[s].e2.isApprox(f[s].axis.cross(f[s].e1), 1e-12));
  }
}

}  // namespace

TEST_CASE("segment_frames: a straight tube cut into segments has one frame", "[segment_frames]") {
  const auto s = synth::capsule(0.5, 4.0, 7, 48, 8, 24, 0, 0.2);
  const auto f = frames_of(s);
  REQUIRE(f.size() == 6);
  check_orthonormal(f, s.skeleton);
  for (const auto& x : f) {
    CHECK(x.axis.isApprox(f[0].axis, 1e-12));  // one orientation along the chain
    CHECK(x.e1.isApprox(f[0].e1, 1e-12));
  }
  // The section is elongated along x: e1 is that principal direction (its sign is the third
  // moment's, checked for stability by the tessellation and rigid-motion tests).
  CHECK(std::abs(f[0].e1.x()) > std::cos(2 * M_PI / 180));
}

TEST_CASE("segment_frames: differently tessellated copies of a shape get corresponding frames", "[segment_frames]") {
  SECTION("tube") {
    const auto a = frames_of(synth::capsule(0.5, 4.0, 5, 48, 8, 24, 0, 0.2));
    const auto b = frames_of(synth::capsule(0.5, 4.0, 5, 37, 6, 31, 0.07, 0.2));
    REQUIRE(a.size() == b.size());
    for (size_t s = 0; s < a.size(); ++s) {
      CHECK(a[s].a == b[s].a);
      CHECK(angle_deg(a[s].e1, b[s].e1) < 5);
    }
  }
  SECTION("Y") {
    const auto ys = synth::ypsilon(40, 20, 0), yt = synth::ypsilon(29, 27, 0.05);
    const auto a = frames_of(ys), b = frames_of(yt);
    check_orthonormal(a, ys.skeleton);
    REQUIRE(a.size() == b.size());
    double worst = 0;
    for (size_t s = 0; s < a.size(); ++s) {
      CHECK(a[s].a == b[s].a);
      worst = std::max(worst, angle_deg(a[s].e1, b[s].e1));
    }
    INFO("worst e1 angle between tessellations " << worst << " degrees");
    CHECK(worst < 5);
  }
}

TEST_CASE("segment_frames: frames follow a rigid motion and ignore node and edge order", "[segment_frames]") {
  const auto y = synth::ypsilon();
  const auto f = frames_of(y);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(2.1, Vector3d(-1, 0.5, 2).normalized()).toRotationMatrix();
  const auto g = frames_of(synth::transformed(y, R, Vector3d(5, -3, 1)));
  for (size_t s = 0; s < f.size(); ++s) {
    CHECK(g[s].a == f[s].a);
    CHECK((g[s].e1 - R * f[s].e1).norm() < 1e-6);
    CHECK((g[s].axis - R * f[s].axis).norm() < 1e-9);
  }
  // Renumber nodes (reversed), reverse every edge and the edge list.
  synth::Shape p = y;
  const int nn = int(y.skeleton.nodes.size()), ne = int(y.skeleton.edges.size());
  for (int i = 0; i < nn; ++i) p.skeleton.nodes[nn - 1 - i] = y.skeleton.nodes[i];
  for (int e = 0; e < ne; ++e) p.skeleton.edges[ne - 1 - e] = {nn - 1 - y.skeleton.edges[e][1], nn - 1 - y.skeleton.edges[e][0]};
  for (auto& n : p.skeleton.vertex_node) n = nn - 1 - n;
  const auto h = frames_of(p);
  for (int e = 0; e < ne; ++e) {
    CHECK(h[ne - 1 - e].a == nn - 1 - f[e].a);
    CHECK((h[ne - 1 - e].e1 - f[e].e1).norm() < 1e-9);
  }
}

TEST_CASE("segment_frames: a ring is carried around its cycle", "[segment_frames]") {
  const auto t = synth::torus(2.0, 0.5, 12);
  const auto f = frames_of(t);
  REQUIRE(f.size() == 12);
  check_orthonormal(f, t.skeleton);
  // A planar ring: transport keeps the angle between e1 and the ring's plane normal, also across
  // the edge that closes the cycle, and the segments run around the ring one way.
  for (size_t s = 0; s < f.size(); ++s) {
    CHECK(std::abs(f[s].e1.z()) == Approx(std::abs(f[0].e1.z())).margin(1e-9));
    const Vector3d mid = 0.5 * (t.skeleton.nodes[f[s].a] + t.skeleton.nodes[f[s].b]);
    const double turn = mid.cross(f[s].axis).z();
    const double turn0 = (0.5 * (t.skeleton.nodes[f[0].a] + t.skeleton.nodes[f[0].b])).cross(f[0].axis).z();
    CHECK(turn * turn0 > 0);
  }
}

TEST_CASE("segment_frames: transport_direction is the minimal rotation", "[segment_frames]") {
  const Vector3d from = Vector3d(1, 0, 0), to = Vector3d(0, 1, 0);
  CHECK(sdm::transport_direction(Vector3d(0, 0, 1), from, to).isApprox(Vector3d(0, 0, 1)));
  CHECK(sdm::transport_direction(Vector3d(0, -1, 0), from, to).isApprox(Vector3d(1, 0, 0)));
  CHECK(sdm::transport_direction(Vector3d(0, 0, 1), from, -from).isApprox(Vector3d(0, 0, 1)));
}
