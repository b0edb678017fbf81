// Posing a decoded SDM through its skeleton (libsdm/pose): rigid away from the joints, volume and
// cross-section kept at a bent or twisted joint, closed and free of self-intersections.
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_sdm.h"
#include "libsdm/pose/deform_decoded.h"
#include "libsdm/pose/pose_skeleton.h"
#include "libsdm/pose/pose_weights.h"
#include "libsdm/pose/smooth_pose_weights.h"
#include "libstm/core/errors.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "libstm/mesh/self_intersections.h"
#include "libstm/mesh/validate_mesh.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "faust_pairs.h"
#include "tests/pose_scenes.h"
#include "libsdm/map/sdm_exr.h"
#include "test_util.h"

#include <filesystem>

#include <catch2/catch.hpp>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

using namespace sdm;
using pose_scenes::Encoded;
using pose_scenes::encode_on;
using pose_scenes::nearest_node;

namespace {

// The capsule primitive (radius 1) with its cylinder stretched from length 2 to 5 (z in [-2.5, 2.5],
// hemispheres centred at z = +-2.5) and its ideal chain skeleton: nodes at z = -2.5, 0, 2.5, each
// vertex on the nearest; two segments 2.5 radii long, kept whole (split_ratio 0).
Encoded encode_capsule() {
  Mesh mesh = make_primitive("capsule", 4000);
  for (auto v : mesh.vertices()) {
    Eigen::Vector3d p = point(mesh, v);
    p.z() = std::abs(p.z()) <= 1 ? 2.5 * p.z() : p.z() + std::copysign(1.5, p.z());
    mesh.set_point(v, Mesh::Point(p.x(), p.y(), p.z()));
  }
  Skeleton s;
  s.nodes = {{0, 0, -2.5}, {0, 0, 0}, {0, 0, 2.5}};
  s.edges = {{0, 1}, {1, 2}};
  for (auto v : mesh.vertices()) s.vertex_node.push_back(int(std::lround(std::clamp(point(mesh, v).z(), -2.5, 2.5) / 2.5)) + 1);
  return encode_on(std::move(mesh), s);
}

// Signed volume (divergence theorem).
double volume(const Mesh& m) {
  double v = 0;
  for (auto f : m.faces()) {
    std::array<Eigen::Vector3d, 3> p;
    int k = 0;
    for (auto x : m.fv_range(f)) p[size_t(k++)] = point(m, x);
    v += p[0].dot(p[1].cross(p[2])) / 6;
  }
  return v;
}

// The points where the mesh's edges cross the plane through `at` with normal n, within `within` of `at`.
std::vector<Eigen::Vector3d> section(const Mesh& m, const Eigen::Vector3d& at, const Eigen::Vector3d& n, double within) {
  std::vector<Eigen::Vector3d> out;
  for (auto e : m.edges()) {
    const auto h = m.halfedge_handle(e, 0);
    const Eigen::Vector3d a = point(m, m.from_vertex_handle(h)), b = point(m, m.to_vertex_handle(h));
    const double da = (a - at).dot(n), db = (b - at).dot(n);
    if ((da < 0) == (db < 0) || da == db) continue;
    const Eigen::Vector3d x = a + da / (da - db) * (b - a);
    if ((x - at).norm() < within) out.push_back(x);
  }
  return out;
}

double min_distance(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& to) {
  double d = INFINITY;
  for (const auto& p : points) d = std::min(d, (p - to).norm());
  return d;
}

long self_intersections(const Mesh& m) { return find_self_intersections(vertex_matrix(m), face_matrix(m)).pairs; }

// Self-intersecting face pairs among the faces whose first corner lies (at rest, in `plain`) within
// `radius` of `c` (near) or not (!near): the rest decode of a real body already has some (FAUST 001
// at 1024, level 3: 3390 pairs over the head, hands, feet and torso; the input 13), so a pose is
// judged by the pairs it adds.
long self_intersections_where(const Mesh& plain, const Mesh& m, const Eigen::Vector3d& c, double radius, bool near) {
  const Eigen::MatrixX3i F = face_matrix(m);
  Eigen::MatrixX3i some(F.rows(), 3);
  int k = 0;
  for (int f = 0; f < F.rows(); ++f)
    if (((point(plain, plain.vertex_handle(F(f, 0))) - c).norm() < radius) == near) some.row(k++) = F.row(f);
  some.conservativeResize(k, 3);
  return find_self_intersections(vertex_matrix(m), some).pairs;
}

bool closed_genus_0(const Mesh& m) {
  const MeshReport r = validate_mesh(mesh_to_soup(m));
  return r.usable() && r.boundary_loops == 0 && r.genus_per_part == std::vector<int>{0};
}


// What a pose must do away from its pivot: the rest decode's vertices farther than `clear` from the
// pivot's rest position are moved by `motion` when the skeleton node nearest them hangs below the
// pivot (`moved`), or stay when it does not (those nearest the pivot itself are left out); the
// largest deviation, and in `checked` how many were compared.
double worst_off_rigid(const Skeleton& rest, const std::vector<char>& moved, int pivot, double clear, const RigidMotion& motion,
                       const Mesh& plain, const Mesh& posed, long* checked) {
  double worst = 0;
  *checked = 0;
  const Eigen::Vector3d c = rest.nodes[size_t(pivot)];
  for (auto v : plain.vertices()) {
    const Eigen::Vector3d p = point(plain, v);
    const int near = nearest_node(rest, p);
    if ((p - c).norm() <= clear || near == pivot) continue;
    const Eigen::Vector3d want = moved[size_t(near)] ? motion(p) : p;
    worst = std::max(worst, (point(posed, posed.vertex_handle(v.idx())) - want).norm());
    ++*checked;
  }
  return worst;
}

}  // namespace

TEST_CASE("A capsule bent 90 degrees at its middle node keeps its volume and its cross-section", "[pose]") {
  const Encoded e = encode_capsule();
  const Skeleton& rest = e.layout.skeleton;
  REQUIRE(rest.nodes.size() == 3);
  const int m = nearest_node(rest, Eigen::Vector3d::Zero());
  const Mesh plain = decode_sdm(e.image);
  const double r = 1.0;  // the capsule's radius (both segments)
  for (double degrees : {90.0}) {
    const Eigen::Quaterniond q(Eigen::AngleAxisd(degrees * M_PI / 180, Eigen::Vector3d::UnitX()));
    PosedSkeleton posed = rest;
    rotate_subtree(rest, posed, m, q);
    const SkeletonPose pose = pose_skeleton(rest, posed);
    std::vector<char> moved(rest.nodes.size(), 0);
    for (int n : subtree_nodes(pose, m)) moved[size_t(n)] = n != m;
    DecodeOptions d;
    d.skeleton = posed;
    const Mesh bent = decode_sdm(e.image, d);
    RigidMotion turn;
    turn.rotation = q;
    turn.translation = rest.nodes[size_t(m)] - q * rest.nodes[size_t(m)];
    long checked = 0;
    const double off = worst_off_rigid(rest, moved, m, 2 * r, turn, plain, bent, &checked);
    // The bisecting plane at the joint: between the unmoved side's direction into the joint and the
    // moved side's out of it.
    int unmoved = -1, child = -1;
    for (const auto& b : pose.bones)
      if (b.head == m || b.tail == m) (moved[size_t(b.head == m ? b.tail : b.head)] ? child : unmoved) = b.head == m ? b.tail : b.head;
    REQUIRE(unmoved >= 0);
    REQUIRE(child >= 0);
    const Eigen::Vector3d joint = posed.nodes[size_t(m)];
    const Eigen::Vector3d in = (joint - posed.nodes[size_t(unmoved)]).normalized(), out = (posed.nodes[size_t(child)] - joint).normalized();
    const double thinnest = min_distance(section(bent, joint, (in + out).normalized(), 2 * r), joint);
    const double v0 = volume(plain), v1 = volume(bent);
    std::printf("capsule bent %.0f deg: volume %.4f -> %.4f (%+.2f %%), joint cross-section %.3f r, off rigid %.2e over %ld vertices\n",
                degrees, v0, v1, 100 * (v1 / v0 - 1), thinnest / r, off, checked);
    CHECK(std::abs(v1 / v0 - 1) <= 0.05);
    CHECK(thinnest >= 0.8 * r);
    CHECK(off <= 1e-9 * 8);
    CHECK(checked > long(plain.n_vertices()) / 3);
    CHECK(closed_genus_0(bent));
    CHECK(self_intersections(bent) == 0);
    // The same weights as a rig's: joints are the bones' heads, 4 weights a vertex summing to 1;
    // far from the joint one joint carries the vertex, at the joint both share it.
    std::vector<Eigen::Vector3d> points;
    for (auto v : plain.vertices()) points.push_back(point(plain, v));
    DecodeTrace trace;
    decode_sdm(e.image, {}, &trace);
    const RigWeights rig = rig_weights(pose, pose_weights(e.layout, points, trace.vertex_segment));
    REQUIRE(rig.joints.size() == points.size());
    CHECK(std::count(rig.node_parent.begin(), rig.node_parent.end(), -1) == 1);
    long shared = 0;
    for (size_t i = 0; i < points.size(); ++i) {
      const auto& w = rig.weights[i];
      CHECK(w[0] + w[1] + w[2] + w[3] == Approx(1).epsilon(1e-6));
      if ((points[i] - rest.nodes[size_t(m)]).norm() > 2 * r) CHECK(w[0] == 1.0f);
      shared += w[1] > 0.1f;
    }
    CHECK(shared > 100);
  }
}

TEST_CASE("A capsule twisted 180 degrees at its middle node keeps its cross-section (no candy wrapper)", "[pose]") {
  const Encoded e = encode_capsule();
  const Skeleton& rest = e.layout.skeleton;
  const int m = nearest_node(rest, Eigen::Vector3d::Zero());
  const Mesh plain = decode_sdm(e.image);
  const SkeletonPose pose = pose_skeleton(rest, rest);
  const std::vector<int> below = subtree_nodes(pose, m);
  REQUIRE(below.size() == 2);
  const Eigen::Vector3d axis = (rest.nodes[size_t(below[1])] - rest.nodes[size_t(m)]).normalized();
  PosedSkeleton posed = rest;
  rotate_subtree(rest, posed, m, Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, axis)));
  DecodeOptions d;
  d.skeleton = posed;
  const Mesh twisted = decode_sdm(e.image, d);
  const double r = 1.0;
  const double thinnest = min_distance(section(twisted, rest.nodes[size_t(m)], axis, 2 * r), rest.nodes[size_t(m)]);
  const double v0 = volume(plain), v1 = volume(twisted);
  const SelfIntersections x = find_self_intersections(vertex_matrix(twisted), face_matrix(twisted));
  std::printf("capsule twisted 180 deg: joint cross-section %.3f r, volume %+.2f %%, %ld self-intersecting pairs (e.g. at %.3f %.3f %.3f; rest %ld)\n",
              thinnest / r, 100 * (v1 / v0 - 1), x.pairs, x.example.x(), x.example.y(), x.example.z(), self_intersections(plain));
  CHECK(thinnest >= 0.8 * r);
  CHECK(std::abs(v1 / v0 - 1) <= 0.05);
  CHECK(closed_genus_0(twisted));
  CHECK(x.pairs == 0);
}

TEST_CASE("Smoothing the blend weights removes a jump, keeps a linear ramp and leaves rigid points alone", "[pose]") {
  const Encoded e = encode_capsule();
  const Skeleton& rest = e.layout.skeleton;
  const int m = nearest_node(rest, Eigen::Vector3d::Zero());
  PosedSkeleton posed = rest;
  rotate_subtree(rest, posed, m, Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ())));  // a half twist
  const SkeletonPose pose = pose_skeleton(rest, posed);
  const Mesh plain = decode_sdm(e.image);
  std::vector<Eigen::Vector3d> points;
  for (auto v : plain.vertices()) points.push_back(point(plain, v));
  const Eigen::MatrixX3i triangles = face_matrix(plain);
  const int below = e.layout.segments[0].a == 0 || e.layout.segments[0].b == 0 ? 0 : 1;  // the segment at z < 0
  // Weights on segment `above` as a function of z, on the segments meeting at z = 0; the points own
  // the segment on their side.
  auto weights_of = [&](const std::function<double(double)>& upper) {
    PoseWeights w;
    w.start = {0};
    for (const auto& p : points) {
      const double u = upper(p.z());
      w.own.push_back(p.z() < 0 ? below : 1 - below);
      w.location.push_back(Eigen::Vector3d(0, 0, p.z()));
      if (u > 0) w.segment.push_back(1 - below), w.weight.push_back(u);
      if (u < 1) w.segment.push_back(below), w.weight.push_back(1 - u);
      w.start.push_back(int(w.segment.size()));
    }
    return w;
  };
  auto upper_weight = [&](const PoseWeights& w, size_t i) {
    double u = 0, sum = 0;
    for (int k = w.start[i]; k < w.start[i + 1]; ++k) {
      sum += w.weight[size_t(k)];
      CHECK(w.weight[size_t(k)] >= 0);
      if (w.segment[size_t(k)] == 1 - below) u += w.weight[size_t(k)];
    }
    CHECK(sum == Approx(1).epsilon(1e-9));
    return u;
  };
  const double r = 1, h = 1.2;  // the capsule's radius, the ramp's half width
  // A linear ramp over |z| < h: refitted by a linear function, it stays as it was inside.
  PoseWeights ramp = weights_of([&](double z) { return std::clamp(0.5 + z / (2 * h), 0.0, 1.0); });
  const PoseWeights ramp_in = ramp;
  smooth_pose_weights(ramp, points, triangles, pose, e.layout);
  double worst_linear = 0;
  for (size_t i = 0; i < points.size(); ++i)
    if (std::abs(points[i].z()) < h - kPoseSmoothRadii * r) worst_linear = std::max(worst_linear, std::abs(upper_weight(ramp, i) - upper_weight(ramp_in, i)));
  // A jump of 0.4 at z = 0 (0.3 below, 0.7 above, ramps to 0 and 1 at |z| = h): spread over the ball.
  PoseWeights jump = weights_of([&](double z) {
    return std::abs(z) >= h ? (z > 0 ? 1.0 : 0.0) : z < 0 ? 0.3 * (1 + z / h) : 0.7 + 0.3 * z / h;
  });
  const PoseWeights jump_in = jump;
  smooth_pose_weights(jump, points, triangles, pose, e.layout);
  double steepest_in = 0, steepest = 0;  // the largest change of the weight along an edge, per unit length
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
    for (int c = 0; c < 3; ++c) {
      const size_t a = size_t(triangles(t, c)), b = size_t(triangles(t, (c + 1) % 3));
      const double length = (points[a] - points[b]).norm();
      steepest_in = std::max(steepest_in, std::abs(upper_weight(jump_in, a) - upper_weight(jump_in, b)) / length);
      steepest = std::max(steepest, std::abs(upper_weight(jump, a) - upper_weight(jump, b)) / length);
    }
  // Rigid points beyond the smoothing's reach keep their single weight exactly.
  long rigid = 0, kept = 0;
  for (size_t i = 0; i < points.size(); ++i)
    if (std::abs(points[i].z()) > h + 1.6 * kPoseSmoothRadii * r + 0.2) {
      ++rigid;
      kept += jump.start[i + 1] - jump.start[i] == 1 && jump.weight[size_t(jump.start[i])] == 1.0;
    }
  std::printf("weight smoothing on a capsule: linear ramp changed by at most %.2e; a jump of 0.4: steepest %.2f -> %.2f per unit; "
              "%ld of %ld rigid points kept\n", worst_linear, steepest_in, steepest, kept, rigid);
  CHECK(worst_linear < 0.01);
  CHECK(steepest_in > 4);          // the jump, across one edge
  CHECK(steepest < 1.5);           // 0.4 spread over about a ball's width (0.5 r each side)
  CHECK(rigid > 1000);
  CHECK(kept == rigid);
}

namespace {

// FAUST 001 (../shared/models/humans) encoded as `sdm encode` does at 1024.
Encoded encode_faust_001() {
  Encoded e;
  e.mesh = load_mesh(faust::humans_dir() + "/tr_reg_001.off").mesh;
  LayoutOptions lo;
  lo.size = 1024;
  e.layout = compute_layout(e.mesh, extract_skeleton(e.mesh), lo);
  e.image = encode_sdm(e.mesh, e.layout);
  return e;
}

// An arm: the chain from the end node farthest out along x (a hand; the body stands along y with its
// arms spread) to the first junction, hand first.
std::vector<int> arm_chain(const Skeleton& s) {
  const auto adj = s.adjacency();
  int hand = -1;
  for (size_t n = 0; n < s.nodes.size(); ++n)
    if (adj[n].size() == 1 && (hand < 0 || s.nodes[n].x() > s.nodes[size_t(hand)].x())) hand = int(n);
  std::vector<int> chain{hand};
  int previous = -1;
  while (adj[size_t(chain.back())].size() <= 2) {
    int next = -1;
    for (int x : adj[size_t(chain.back())])
      if (x != previous) next = x;
    if (next < 0) break;
    previous = chain.back();
    chain.push_back(next);
  }
  return chain;
}

}  // namespace

TEST_CASE("FAUST 001 posed at the middle of an arm turns the forearm rigidly and stays closed", "[pose][faust]") {
  if (!faust::have("tr_reg_001.off")) {
    WARN("../shared/models/humans/tr_reg_001.off is missing: skipped");
    return;
  }
  const Encoded e = encode_faust_001();
  const Skeleton& rest = e.layout.skeleton;
  const std::vector<int> chain = arm_chain(rest);
  REQUIRE(chain.size() >= 3);
  const int m = chain[chain.size() / 2];
  const SkeletonPose pose0 = pose_skeleton(rest, rest);
  const std::vector<int> below = subtree_nodes(pose0, m);
  std::vector<char> moved(rest.nodes.size(), 0);
  for (int n : below) moved[size_t(n)] = n != m;
  REQUIRE(moved[size_t(chain.front())]);  // the hand hangs below m
  // The local radius: the larger of the two segments meeting at m.
  double r = 0;
  int child = -1;
  for (size_t s = 0; s < pose0.bones.size(); ++s)
    if (pose0.bones[s].head == m || pose0.bones[s].tail == m) {
      r = std::max(r, e.layout.segments[s].radius);
      if (pose0.bones[s].head == m) child = pose0.bones[s].tail;
    }
  REQUIRE(child >= 0);
  const Mesh plain = decode_sdm(e.image);
  const double diag = bounding_box_diagonal(plain);
  const Eigen::Vector3d c = rest.nodes[size_t(m)];
  const long near_rest = self_intersections_where(plain, plain, c, 4 * r, true), away_rest = self_intersections_where(plain, plain, c, 4 * r, false);
  const Eigen::Vector3d forearm = (rest.nodes[size_t(chain.front())] - c).normalized();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (auto v : plain.vertices()) centroid += point(plain, v);
  centroid /= double(plain.n_vertices());
  Eigen::Vector3d away = c - centroid;
  away = (away - away.dot(forearm) * forearm).normalized();
  const Eigen::Vector3d bend_axis = forearm.cross(away).normalized();  // turning about it moves the forearm towards `away`
  struct Case {
    std::string name;
    Eigen::Quaterniond q;
  };
  const Eigen::Vector3d twist_axis = (rest.nodes[size_t(child)] - c).normalized();
  const std::vector<Case> cases = {{"bend 30", Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 6, bend_axis))},
                                   {"bend 60", Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 3, bend_axis))},
                                   {"bend 90", Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, bend_axis))},
                                   {"twist 90", Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, twist_axis))}};
  for (const Case& k : cases) {
    PosedSkeleton posed = rest;
    rotate_subtree(rest, posed, m, k.q);
    DecodeOptions d;
    d.skeleton = posed;
    const Mesh out = decode_sdm(e.image, d);
    RigidMotion turn;
    turn.rotation = k.q;
    turn.translation = c - k.q * c;
    long checked = 0;
    const double off = worst_off_rigid(rest, moved, m, 2 * r, turn, plain, out, &checked);
    const long near = self_intersections_where(plain, out, c, 4 * r, true), away = self_intersections_where(plain, out, c, 4 * r, false);
    std::printf("FAUST 001 %s at node %d (local radius %.4f): off rigid %.2e %% of the diagonal over %ld of %zu vertices; "
                "self-intersecting pairs within 4 radii of the pivot %ld (rest %ld), elsewhere %ld (rest %ld)\n",
                k.name.c_str(), m, r, 100 * off / diag, checked, out.n_vertices(), near, near_rest, away, away_rest);
    INFO(k.name);
    CHECK(off <= 0.0005 * diag);
    CHECK(checked > long(out.n_vertices()) * 8 / 10);
    CHECK(closed_genus_0(out));
    CHECK(away == away_rest);          // nothing new away from the joint
    CHECK(near <= near_rest);          // no face pair crosses at the joint that did not at rest
  }
}

namespace {

// The middle node of the longest chain of `s` that starts at an end node (-1 when no chain has 3
// nodes), and the chain's direction there.
int chain_middle(const Skeleton& s, Eigen::Vector3d* direction) {
  const auto adj = s.adjacency();
  std::vector<int> best;
  for (size_t end = 0; end < s.nodes.size(); ++end) {
    if (adj[end].size() != 1) continue;
    std::vector<int> chain{int(end)};
    int previous = -1;
    while (true) {
      const int u = chain.back();
      if (chain.size() > 1 && adj[size_t(u)].size() != 2) break;
      int next = -1;
      for (int x : adj[size_t(u)])
        if (x != previous) next = x;
      if (next < 0 || std::find(chain.begin(), chain.end(), next) != chain.end()) break;
      previous = u;
      chain.push_back(next);
    }
    if (chain.size() > best.size()) best = chain;
  }
  if (best.size() < 3) return -1;
  const size_t m = best.size() / 2;
  *direction = (s.nodes[size_t(best[m - 1])] - s.nodes[size_t(best[m + 1])]).normalized();
  return best[m];
}

std::string topology_of(const Mesh& m) {
  const MeshReport r = validate_mesh(mesh_to_soup(m));
  std::string t = std::to_string(r.genus_per_part.size()) + " part(s), genus";
  for (int g : r.genus_per_part) t += " " + std::to_string(g);
  return t + ", " + std::to_string(r.boundary_loops) + " boundary loop(s)";
}

}  // namespace

// Every model of ../shared/models through the pose a user tries first: the part below the middle
// node of the longest limb turned 45 degrees about an axis across it, decoded at level 2. Hidden
// (about 35 s); the figures are in docs/BENCHMARKS.md, "Posing through the skeleton".
TEST_CASE("Every shared model turned 45 degrees at its longest limb keeps its topology", "[.pose_models]") {
  const std::string root = faust::humans_dir() + "/..";
  std::vector<std::string> files;
  for (const auto& dir : {"spot", "cgal", "humans", "wild"}) {
    if (!std::filesystem::is_directory(root + "/" + dir)) continue;
    for (const auto& f : std::filesystem::directory_iterator(root + "/" + dir)) {
      const std::string ext = f.path().extension().string();
      if (ext == ".obj" || ext == ".off") files.push_back(f.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  for (const std::string& file : files) {
    INFO(file);
    Encoded e;
    try {
      e.mesh = load_mesh(file, LoadOptions{}).mesh;
      LayoutOptions lo;
      lo.size = 1024;
      e.layout = compute_layout(e.mesh, extract_skeleton(e.mesh), lo);
      e.image = encode_sdm(e.mesh, e.layout);
    } catch (const std::exception& x) {
      std::printf("%s: not encoded (%s)\n", file.c_str(), x.what());
      continue;
    }
    const Skeleton& rest = e.layout.skeleton;
    Eigen::Vector3d along;
    const int m = chain_middle(rest, &along);
    if (m < 0) {
      std::printf("%s: no chain of 3 nodes to turn\n", file.c_str());
      continue;
    }
    double r = 0;
    for (const auto& seg : e.layout.segments)
      if (seg.a == m || seg.b == m) r = std::max(r, seg.radius);
    Eigen::Vector3d axis = along.unitOrthogonal();
    PosedSkeleton posed = rest;
    rotate_subtree(rest, posed, m, Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 4, axis)));
    DecodeOptions d;
    d.level = 2;
    const Mesh plain = decode_sdm(e.image, d);
    d.skeleton = posed;
    const Mesh out = decode_sdm(e.image, d);
    const Eigen::Vector3d c = rest.nodes[size_t(m)];
    const long near_rest = self_intersections_where(plain, plain, c, 4 * r, true);
    const long near = self_intersections_where(plain, out, c, 4 * r, true);
    const long joint_rest = self_intersections_where(plain, plain, c, 1.5 * r, true);
    const long joint = self_intersections_where(plain, out, c, 1.5 * r, true);
    std::printf("%s: node %d of %zu turned 45 deg (radius %.3g): %s -> %s; crossing pairs within 4 radii %ld (rest %ld), 1.5 radii %ld (rest %ld)\n",
                file.c_str(), m, rest.nodes.size(), r, topology_of(plain).c_str(), topology_of(out).c_str(), near, near_rest, joint, joint_rest);
    CHECK(topology_of(out) == topology_of(plain));
    // Known gap (DECISIONS 4, "Posing"): five of the CGAL and wild shapes (anchor, mech-holes-shark,
    // retinal, rotor, beetle) cross 1-151 more face pairs within 1.5 radii of the joint.
    CHECK_NOFAIL(joint <= joint_rest);
  }
}

TEST_CASE("sdm pose turns, twists and thickens from the command line and refuses bad options with exit 2", "[pose]") {
  const Encoded e = encode_capsule();
  test_util::TempDir dir;
  write_sdm_exr(e.image, dir / "capsule.exr");
  const int m = nearest_node(e.layout.skeleton, Eigen::Vector3d::Zero());
  const std::string base = "pose " + (dir / "capsule.exr") + " --lod 2 ";
  auto res = test_util::run_sdm(base + "-o " + (dir / "bent.obj") + " --rotate " + std::to_string(m) + "=x,90 --rotate " +
                                std::to_string(m) + "=twist,45 --write-skeleton " + (dir / "posed.json") + " --json");
  INFO(res.output);
  REQUIRE(res.exit_code == 0);
  const nlohmann::json j = test_util::last_json(res);
  CHECK(j.at("closed").get<bool>());
  // The far end turned 90 degrees about the middle node: its tip, 3.5 away, moves 3.5 sqrt(2); the
  // twist of 45 degrees about the turned axis adds at most 2 sin(22.5 degrees) (radius 1).
  const double moved = j.at("max_displacement").get<double>();
  CHECK(moved >= 0.98 * 3.5 * std::sqrt(2.0));
  CHECK(moved <= 3.5 * std::sqrt(2.0) + 2 * std::sin(M_PI / 8) + 0.01);
  const PosedSkeleton posed = read_posed_skeleton_json(dir / "posed.json");
  REQUIRE(posed.node_rotations.size() == posed.nodes.size());
  // The posed skeleton decodes to the same surface through sdm decode --skeleton.
  res = test_util::run_sdm("decode " + (dir / "capsule.exr") + " --lod 2 --skeleton " + (dir / "posed.json") + " -o " + (dir / "again.obj"));
  REQUIRE(res.exit_code == 0);
  const Mesh a = load_mesh(dir / "bent.obj").mesh, b = load_mesh(dir / "again.obj").mesh;
  REQUIRE(a.n_vertices() == b.n_vertices());
  double apart = 0;
  for (auto v : a.vertices()) apart = std::max(apart, (point(a, v) - point(b, v)).norm());
  CHECK(apart < 1e-5);
  // Twice the radius of both segments: the volume of a capsule of radius 2 and length 5.
  res = test_util::run_sdm(base + "-o " + (dir / "fat.obj") + " --scale-radius 0=2 --scale-radius 1=2");
  REQUIRE(res.exit_code == 0);
  CHECK(volume(load_mesh(dir / "fat.obj").mesh) == Approx(M_PI * 4 * 5 + 4.0 / 3 * M_PI * 8).epsilon(0.03));
  for (const std::string bad : {"--rotate 999=x,10", "--rotate 1=w,10", "--scale-radius 0=-1", "--scale-radius 9=2"}) {
    res = test_util::run_sdm(base + "-o " + (dir / "bad.obj") + " " + bad);
    INFO(bad << ": " << res.output);
    CHECK(res.exit_code == 2);
    CHECK(!std::filesystem::exists(dir / "bad.obj"));
  }
}
