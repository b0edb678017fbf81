// `sdm decode --rig` and `sdm pose --rig` (libsdm/pose/rig_skin.h): the decoded mesh at rest with a
// glTF skin whose joints are the map's skeleton nodes, posed by linear blend skinning as sdm pose
// poses it (dual quaternions) up to the blend near the joint.
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_sdm.h"
#include "libsdm/map/sdm_exr.h"
#include "libsdm/pose/pose_skeleton.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/gltf_skin.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "tests/glb_check.h"
#include "tests/pose_scenes.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

using namespace sdm;
using pose_scenes::Encoded;
using pose_scenes::encode_on;
using pose_scenes::nearest_node;

namespace {

// The ypsilon primitive (tubes of radius 0.22 from the origin to (0, -1.1, 0), (-0.78, 0.78, 0) and
// (0.78, 0.78, 0)) with its ideal skeleton: the junction at the origin, the three ends, and a node
// halfway along the left arm (a bend there turns the outer half of the arm); every vertex on the
// nearest node; segments kept whole (split_ratio 0).
const Eigen::Vector3d kMidLeft(-0.39, 0.39, 0);

Encoded encode_ypsilon() {
  Mesh mesh = make_primitive("ypsilon", 3000);
  Skeleton s;
  s.nodes = {{0, 0, 0}, {0, -1.1, 0}, kMidLeft, {-0.78, 0.78, 0}, {0.78, 0.78, 0}};
  s.edges = {{0, 1}, {0, 2}, {2, 3}, {0, 4}};
  for (auto v : mesh.vertices()) s.vertex_node.push_back(nearest_node(s, point(mesh, v)));
  return encode_on(std::move(mesh), s);
}

// The written vertices (POSITION) with their influences (JOINTS_0, WEIGHTS_0), in the file's order.
struct Skinned {
  std::vector<Eigen::Vector3d> x;
  std::vector<double> joints, weights;
};
std::vector<Eigen::Vector3d> skinned_positions(const glb_check::Glb& g) {
  const std::vector<double> x = glb_check::accessor_values(g, g.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"]);
  std::vector<Eigen::Vector3d> out;
  for (size_t v = 0; v < x.size() / 3; ++v) out.emplace_back(x[3 * v], x[3 * v + 1], x[3 * v + 2]);
  return out;
}
Skinned skinned_vertices(const glb_check::Glb& g) {
  const auto& attr = g.json["meshes"][0]["primitives"][0]["attributes"];
  Skinned s;
  s.x = skinned_positions(g);
  s.joints = glb_check::accessor_values(g, attr["JOINTS_0"]);
  s.weights = glb_check::accessor_values(g, attr["WEIGHTS_0"]);
  return s;
}

// Linear blend skinning: vertex v moved by sum_k w_k M_{j_k}, with M_j the motion of joint j.
std::vector<Eigen::Vector3d> blend(const Skinned& s, const std::vector<Eigen::Affine3d>& motion) {
  std::vector<Eigen::Vector3d> out;
  for (size_t v = 0; v < s.x.size(); ++v) {
    Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
    for (size_t k = 0; k < 4; ++k) m += s.weights[4 * v + k] * motion[size_t(s.joints[4 * v + k])].matrix();
    out.push_back((m * s.x[v].homogeneous()).head<3>());
  }
  return out;
}

// A node's global transform from the file's node tree (translation * rotation per node).
Eigen::Affine3d node_global(const nlohmann::json& j, int node) {
  std::vector<int> parent(j["nodes"].size(), -1);
  for (size_t n = 0; n < parent.size(); ++n)
    for (const auto& c : j["nodes"][n].value("children", nlohmann::json::array())) parent[c.get<size_t>()] = int(n);
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  for (int k = node; k >= 0; k = parent[size_t(k)]) {
    const auto& n = j["nodes"][size_t(k)];
    Eigen::Affine3d local = Eigen::Affine3d::Identity();
    if (n.contains("translation")) local.translate(Eigen::Vector3d(n["translation"][0], n["translation"][1], n["translation"][2]));
    if (n.contains("rotation"))
      local.rotate(Eigen::Quaterniond(n["rotation"][3].get<double>(), n["rotation"][0], n["rotation"][1], n["rotation"][2]));
    t = local * t;
  }
  return t;
}

// A rigged file's vertices skinned by its own joint nodes (as a viewer opens it), after checking
// its structure and that its bind pose is `rest`'s nodes.
std::vector<Eigen::Vector3d> opened_posed(const std::string& path, const Skeleton& rest) {
  glb_check::check_glb_structure(path);
  const glb_check::Glb h = glb_check::read_glb(path);
  const std::vector<int> joints = h.json["skins"][0]["joints"];
  const GltfSkin bind = read_gltf_skin(path);
  REQUIRE(joints.size() == rest.nodes.size());
  std::vector<Eigen::Affine3d> from_file;
  for (size_t j = 0; j < joints.size(); ++j) {
    CHECK((bind.joint_position[j] - rest.nodes[j]).norm() < 1e-6);
    from_file.push_back(node_global(h.json, joints[j]) * Eigen::Translation3d(-bind.joint_position[j]));
  }
  return blend(skinned_vertices(h), from_file);
}

}  // namespace

TEST_CASE("sdm decode --rig writes the decoded ypsilon with a skin on its skeleton nodes that poses as sdm pose does", "[rig]") {
  const Encoded e = encode_ypsilon();
  const Skeleton& rest = e.layout.skeleton;
  test_util::TempDir dir;
  write_sdm_exr(e.image, dir / "y.exr");
  auto res = test_util::run_sdm("decode " + (dir / "y.exr") + " --lod 2 --rig -o " + (dir / "rig.glb"));
  INFO(res.output);
  REQUIRE(res.exit_code == 0);
  glb_check::check_glb_structure(dir / "rig.glb");
  const GltfSkin skin = read_gltf_skin(dir / "rig.glb");
  // One joint per node at its rest position, named after it, parented by a tree rooted at the junction.
  REQUIRE(skin.joint_position.size() == rest.nodes.size());
  const int junction = nearest_node(rest, Eigen::Vector3d::Zero());
  const std::vector<std::vector<int>> adjacent = rest.adjacency();
  int roots = 0;
  for (size_t j = 0; j < rest.nodes.size(); ++j) {
    CHECK((skin.joint_position[j] - rest.nodes[j]).norm() < 1e-6);
    CHECK(skin.joint_name[j] == "node " + std::to_string(j));
    const int p = skin.joint_parent[j];
    if (p < 0) {
      ++roots;
      CHECK(int(j) == junction);
    } else {
      CHECK(std::find(adjacent[j].begin(), adjacent[j].end(), p) != adjacent[j].end());
    }
  }
  CHECK(roots == 1);
  for (const auto& w : skin.vertex_weights) CHECK(std::abs(double(w[0]) + w[1] + w[2] + w[3] - 1) < 1e-6);

  // The outer half of the left arm turned 60 degrees in the ypsilon's plane: linear blend skinning
  // of the file (the joints below the mid-left node turned about it) against sdm pose.
  const int mid = nearest_node(rest, kMidLeft);
  PosedSkeleton posed = rest;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(M_PI / 3, Eigen::Vector3d::UnitZ()));
  rotate_subtree(rest, posed, mid, q);
  const std::vector<int> below = subtree_nodes(pose_skeleton(rest, posed), mid);
  std::vector<Eigen::Affine3d> motion(rest.nodes.size(), Eigen::Affine3d::Identity());
  for (int n : below) motion[size_t(n)] = Eigen::Translation3d(rest.nodes[size_t(mid)]) * q * Eigen::Translation3d(-rest.nodes[size_t(mid)]);
  const glb_check::Glb g = glb_check::read_glb(dir / "rig.glb");
  const Skinned s = skinned_vertices(g);
  const std::vector<Eigen::Vector3d> lbs = blend(s, motion);
  const std::string rotate = " --rotate " + std::to_string(mid) + "=z,60";
  // Written as .glb too, so that its vertices come in the rigged file's order (an OBJ reads back
  // in another).
  res = test_util::run_sdm("pose " + (dir / "y.exr") + " --lod 2" + rotate + " -o " + (dir / "posed-dq.glb"));
  REQUIRE(res.exit_code == 0);
  const std::vector<Eigen::Vector3d> dq = skinned_positions(glb_check::read_glb(dir / "posed-dq.glb"));
  REQUIRE(dq.size() == s.x.size());
  Eigen::AlignedBox3d box;
  for (const auto& x : dq) box.extend(x);
  const double diag = box.diagonal().norm();
  double single = 0, sum2 = 0, worst = 0;
  long n_single = 0, n_turned = 0;
  for (size_t v = 0; v < s.x.size(); ++v) {
    const double d = (lbs[v] - dq[v]).norm();
    sum2 += d * d;
    worst = std::max(worst, d);
    if (s.weights[4 * v] == 1.0) {
      single = std::max(single, d), ++n_single;
      if (std::find(below.begin(), below.end(), int(s.joints[4 * v])) != below.end()) ++n_turned;
    }
  }
  const double rms = std::sqrt(sum2 / double(s.x.size()));
  std::printf("ypsilon rigged (%zu vertices, %zu joints), left arm bent 60 deg: %ld vertices on one joint (%ld turned) within %.2e of the "
              "diagonal; LBS vs sdm pose RMS %.4f %%, largest %.3f %% of the diagonal\n",
              s.x.size(), rest.nodes.size(), n_single, n_turned, single / diag, 100 * rms / diag, 100 * worst / diag);
  CHECK(n_turned > 50);
  CHECK(single < 1e-5 * diag);
  CHECK(rms < 0.005 * diag);

  CHECK(worst < 0.02 * diag);

  // sdm pose --rig, and sdm decode --skeleton --rig with its posed skeleton: the same mesh at rest,
  // the joints holding the pose, so that the file's own node transforms skin it as the turn above.
  res = test_util::run_sdm("pose " + (dir / "y.exr") + " --lod 2" + rotate + " --rig -o " + (dir / "posed.glb") + " --write-skeleton " +
                           (dir / "posed.json"));
  REQUIRE(res.exit_code == 0);
  res = test_util::run_sdm("decode " + (dir / "y.exr") + " --lod 2 --skeleton " + (dir / "posed.json") + " --rig -o " + (dir / "d.glb"));
  REQUIRE(res.exit_code == 0);
  for (const std::string file : {"posed.glb", "d.glb"}) {
    const std::vector<Eigen::Vector3d> opened = opened_posed(dir / file, rest);
    REQUIRE(opened.size() == lbs.size());
    double apart = 0;
    for (size_t v = 0; v < opened.size(); ++v) apart = std::max(apart, (opened[v] - lbs[v]).norm());
    INFO(file);
    CHECK(apart < 1e-5 * diag);
  }

  // --rig needs a glTF output: exit 2, nothing written.
  for (const std::string cmd : {"decode ", "pose "}) {
    res = test_util::run_sdm(cmd + (dir / "y.exr") + " --rig -o " + (dir / "rig.obj"));
    INFO(res.output);
    CHECK(res.exit_code == 2);
    CHECK(!std::filesystem::exists(dir / "rig.obj"));
  }
}

TEST_CASE("A pose given in single precision (Blender, glTF) decodes as the exact pose", "[rig][pose]") {
  // The outer half of the ypsilon's left arm turned 60 degrees; the same pose with every node
  // position and rotation rounded to float32, as a Blender armature or a glTF skin holds it.
  const Encoded e = encode_ypsilon();
  const Skeleton& rest = e.layout.skeleton;
  const int mid = nearest_node(rest, kMidLeft);
  PosedSkeleton exact = rest;
  rotate_subtree(rest, exact, mid, Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 3, Eigen::Vector3d::UnitZ())));
  PosedSkeleton rounded = exact;
  for (auto& p : rounded.nodes) p = p.cast<float>().cast<double>();
  for (auto& q : rounded.node_rotations)
    if (q) q = Eigen::Quaterniond(q->coeffs().cast<float>().cast<double>()).normalized();
  DecodeOptions a, b;
  a.level = b.level = 2;
  a.skeleton = exact;
  b.skeleton = rounded;
  const Mesh ma = decode_sdm(e.image, a), mb = decode_sdm(e.image, b);
  REQUIRE(ma.n_vertices() == mb.n_vertices());
  double worst = 0;
  for (auto v : ma.vertices()) worst = std::max(worst, (point(ma, v) - point(mb, v)).norm());
  const double diag = bounding_box_diagonal(ma);
  std::printf("ypsilon arm turned 60 deg, pose rounded to float32: largest vertex difference %.2e of the diagonal\n", worst / diag);
  CHECK(worst <= 1e-6 * diag);
}
