// Rigged glTF (libstm/mesh/gltf_skin.h): a capsule with a 3-joint chain written as .glb passes the
// structural checks (tests/glb_check.h) and the glTF validator's skin rules (checked here), reads
// back with its joints and weights, and posed by linear blend skinning from the file's own nodes,
// inverse bind matrices, joints and weights moves as the rotation of the turned joint says; a
// forest of joints, more than 256 joints, uv seams (Spot), bad skins and malformed files.
#include "libstm/core/errors.h"
#include "libstm/mesh/gltf_skin.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/primitives.h"
#include "tests/glb_check.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <functional>
#include <map>
#include <set>

namespace {

using namespace glb_check;

const std::string kSpot = std::string(SDM_EXAMPLES) + "/spot/spot_triangulated.obj";
const std::string kSpotTexture = std::string(SDM_EXAMPLES) + "/spot/spot_texture.png";

// Each node's parent in the file (-1 for none).
std::vector<int> node_parents(const nlohmann::json& j) {
  std::vector<int> parent(j.at("nodes").size(), -1);
  for (size_t n = 0; n < parent.size(); ++n)
    for (const auto& c : j["nodes"][n].value("children", nlohmann::json::array())) {
      REQUIRE(parent[c.get<size_t>()] == -1);
      parent[c.get<size_t>()] = int(n);
    }
  return parent;
}

// A node's global transform, its local one (translation * rotation * scale) turned by `turn[node]`
// (identity where absent) about its origin, as a posing application does.
Eigen::Affine3d node_global(const nlohmann::json& j, const std::vector<int>& parent, int node,
                            const std::map<int, Eigen::Matrix3d>& turn = {}) {
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  for (int k = node; k >= 0; k = parent[size_t(k)]) {
    const auto& n = j["nodes"][size_t(k)];
    REQUIRE(!n.contains("matrix"));
    Eigen::Affine3d local = Eigen::Affine3d::Identity();
    auto get = [&](const char* key, int i) { return n[key][i].get<double>(); };
    if (n.contains("translation")) local.translate(Eigen::Vector3d(get("translation", 0), get("translation", 1), get("translation", 2)));
    if (n.contains("rotation")) local.rotate(Eigen::Quaterniond(get("rotation", 3), get("rotation", 0), get("rotation", 1), get("rotation", 2)));
    if (n.contains("scale")) local.scale(Eigen::Vector3d(get("scale", 0), get("scale", 1), get("scale", 2)));
    if (turn.count(k)) local.rotate(turn.at(k));
    t = local * t;
  }
  return t;
}

// The validator's influence rules (glTF-Validator's InfluencesChecker) on one primitive: JOINTS_0
// unsigned byte (256 joints or fewer) or short, WEIGHTS_0 float, both VEC4 on vertex buffer views
// aligned to 4 bytes; per vertex no joint beyond the skin, a joint of weight > 0 named once, no
// negative weight, joint 0 in slots of weight 0, and the weights' float sum (slot by slot) 1:
// exactly for one or two joints, within 1/255 for three or four.
void check_influences(const Glb& g, const nlohmann::json& primitive, size_t joint_count) {
  const auto& attr = primitive.at("attributes");
  const int ja = attr.at("JOINTS_0"), wa = attr.at("WEIGHTS_0");
  const auto& J = g.json["accessors"][ja];
  const auto& W = g.json["accessors"][wa];
  REQUIRE(J.at("type") == "VEC4");
  REQUIRE(J.at("componentType") == (joint_count <= 256 ? 5121 : 5123));
  REQUIRE(W.at("type") == "VEC4");
  REQUIRE(W.at("componentType") == 5126);
  for (const auto* a : {&J, &W}) {
    const auto& v = g.json["bufferViews"][a->at("bufferView").get<size_t>()];
    REQUIRE(v.at("target") == 34962);
    REQUIRE(v.value("byteOffset", 0) % 4 == 0);
    REQUIRE(a->value("byteOffset", 0) % 4 == 0);
  }
  const std::vector<double> js = accessor_values(g, ja), ws = accessor_values(g, wa);
  long bad = 0;
  for (size_t v = 0; v < js.size() / 4; ++v) {
    float sum = 0;
    std::set<int> used;
    for (int k = 0; k < 4; ++k) {
      const int joint = int(js[4 * v + k]);
      const float w = float(ws[4 * v + k]);
      bad += joint >= int(joint_count);
      if (w != 0) {
        bad += !used.insert(joint).second;
        bad += w < 0;
        sum = sum + w;
      } else {
        bad += joint != 0;
      }
    }
    const double threshold = 0.0039216 * (int((used.size() + 1) >> 1) - 1);
    bad += std::abs(double(sum) - 1.0) > threshold;
  }
  INFO(bad << " influence rules broken");
  CHECK(bad == 0);
}

// The validator's skin rules: one skin, its joints distinct nodes of the scene, `skeleton` a common
// root of them, inverse bind matrices float MAT4 one per joint on a view with no target and no
// stride, each with last row (0, 0, 0, 1) and (checked further than the validator does) the
// inverse of its joint's global rest transform; the skinned mesh node a root of the scene without
// transform, its primitives' influences as check_influences says.
void check_skin_rules(const Glb& g) {
  const auto& j = g.json;
  const std::vector<int> parent = node_parents(j);
  std::vector<char> in_scene(parent.size(), 0);
  std::function<void(int)> mark = [&](int n) {
    in_scene[size_t(n)] = 1;
    for (const auto& c : j["nodes"][size_t(n)].value("children", nlohmann::json::array())) mark(c);
  };
  for (const auto& n : j.at("scenes")[0].at("nodes")) mark(n);
  REQUIRE(j.at("skins").size() == 1);
  const auto& skin = j["skins"][0];
  const std::vector<int> joints = skin.at("joints");
  REQUIRE(std::set<int>(joints.begin(), joints.end()).size() == joints.size());
  const int skeleton = skin.at("skeleton");
  for (int n : joints) {
    REQUIRE(in_scene[size_t(n)]);
    int k = n;
    while (k >= 0 && k != skeleton) k = parent[size_t(k)];
    REQUIRE(k == skeleton);
  }
  const int ibm = skin.at("inverseBindMatrices");
  const auto& ia = j["accessors"][ibm];
  REQUIRE(ia.at("type") == "MAT4");
  REQUIRE(ia.at("componentType") == 5126);
  REQUIRE(ia.at("count") == joints.size());
  const auto& iv = j["bufferViews"][ia.at("bufferView").get<size_t>()];
  REQUIRE(!iv.contains("target"));
  REQUIRE(!iv.contains("byteStride"));
  const std::vector<double> m = accessor_values(g, ibm);
  double worst = 0;
  for (size_t k = 0; k < joints.size(); ++k) {
    Eigen::Matrix4d a;
    for (int c = 0; c < 16; ++c) a(c % 4, c / 4) = m[16 * k + size_t(c)];
    REQUIRE(a.row(3) == Eigen::RowVector4d(0, 0, 0, 1));
    worst = std::max(worst, (a * node_global(j, parent, joints[k]).matrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff());
  }
  CHECK(worst < 1e-6);
  int skinned = 0;
  for (size_t n = 0; n < parent.size(); ++n) {
    const auto& node = j["nodes"][n];
    if (!node.contains("skin")) continue;
    ++skinned;
    REQUIRE(node.contains("mesh"));
    for (const char* key : {"translation", "rotation", "scale", "matrix"}) CHECK(!node.contains(key));
    CHECK(parent[n] == -1);
    CHECK(in_scene[n]);
    for (const auto& p : j["meshes"][node["mesh"].get<size_t>()].at("primitives")) check_influences(g, p, joints.size());
  }
  CHECK(skinned == 1);
}

// The file's vertices posed by linear blend skinning (glTF 2.0, "Skins"): joint k's node turned by
// turn[k] about its origin, each vertex moved by sum_k w_k * global(joint_k) * inverseBind(joint_k),
// everything read from the file (POSITION, JOINTS_0, WEIGHTS_0, nodes, inverse bind matrices).
std::vector<Eigen::Vector3d> pose(const Glb& g, const std::map<int, Eigen::Matrix3d>& turn_joint) {
  const auto& j = g.json;
  const std::vector<int> parent = node_parents(j);
  const std::vector<int> joints = j["skins"][0]["joints"];
  std::map<int, Eigen::Matrix3d> turn;
  for (const auto& [k, r] : turn_joint) turn[joints[size_t(k)]] = r;
  const std::vector<double> m = accessor_values(g, j["skins"][0]["inverseBindMatrices"]);
  std::vector<Eigen::Matrix4d> skinning(joints.size());
  for (size_t k = 0; k < joints.size(); ++k) {
    Eigen::Matrix4d ibm;
    for (int c = 0; c < 16; ++c) ibm(c % 4, c / 4) = m[16 * k + size_t(c)];
    skinning[k] = node_global(j, parent, joints[k], turn).matrix() * ibm;
  }
  const auto& attr = j["meshes"][0]["primitives"][0]["attributes"];
  const std::vector<double> x = accessor_values(g, attr["POSITION"]), js = accessor_values(g, attr["JOINTS_0"]),
                            ws = accessor_values(g, attr["WEIGHTS_0"]);
  std::vector<Eigen::Vector3d> out;
  for (size_t v = 0; v < x.size() / 3; ++v) {
    Eigen::Matrix4d s = Eigen::Matrix4d::Zero();
    for (int k = 0; k < 4; ++k) s += ws[4 * v + size_t(k)] * skinning[size_t(js[4 * v + size_t(k)])];
    out.push_back((s * Eigen::Vector4d(x[3 * v], x[3 * v + 1], x[3 * v + 2], 1)).head<3>());
  }
  return out;
}

// The capsule (axis z, from z = -2 to 2) with a chain root (z = -2), middle (z = 0), tip (z = 1):
// weight 1 on the root below z = -0.5, a linear ramp to the middle joint across it (z in
// [-0.5, 0.5]), 1 on the middle up to 0.75, a ramp to the tip across it (z in [0.75, 1.25]), 1 on
// the tip above. Slots: lower joint, upper joint, then two of weight 0 naming joint -1 (the writer
// writes joint 0 there).
const double kJointZ[3] = {-2, 0, 1};

std::pair<std::array<int, 4>, std::array<float, 4>> chain_influence(double z) {
  auto ramp = [](int a, int b, double t) {
    return std::make_pair(std::array<int, 4>{a, b, -1, -1}, std::array<float, 4>{float(1 - t), float(t), 0, 0});
  };
  if (z <= -0.5) return ramp(0, 1, 0);
  if (z < 0.5) return ramp(0, 1, z + 0.5);
  if (z <= 0.75) return ramp(1, 2, 0);
  if (z < 1.25) return ramp(1, 2, (z - 0.75) / 0.5);
  return ramp(1, 2, 1);
}

struct Rig {
  sdm::Mesh mesh;
  sdm::GltfSkin skin;
};

Rig capsule_rig() {
  Rig r{sdm::make_primitive("capsule"), {}};
  for (double z : kJointZ) r.skin.joint_position.emplace_back(0, 0, z);
  r.skin.joint_parent = {-1, 0, 1};
  r.skin.joint_name = {"root", "middle", "tip"};
  for (auto v : r.mesh.vertices()) {
    const auto [j, w] = chain_influence(r.mesh.point(v)[2]);
    r.skin.vertex_joints.push_back(j);
    r.skin.vertex_weights.push_back(w);
  }
  return r;
}

// The mesh vertex at each point read back (points are the file's float positions).
std::vector<int> vertex_of_points(const sdm::Mesh& mesh, const std::vector<Eigen::Vector3d>& points) {
  std::map<std::array<float, 3>, int> at;
  for (auto v : mesh.vertices()) at[{float(mesh.point(v)[0]), float(mesh.point(v)[1]), float(mesh.point(v)[2])}] = v.idx();
  std::vector<int> out;
  for (const auto& p : points) {
    const auto it = at.find({float(p.x()), float(p.y()), float(p.z())});
    REQUIRE(it != at.end());
    out.push_back(it->second);
  }
  return out;
}

// The largest difference between the weights read at each point and those given to its vertex
// (joints compared where the weight is > 0); counts the points whose weights do not sum to 1.
double weight_difference(const Rig& r, const sdm::GltfSkin& back, const std::vector<int>& vertex, long& joint_mismatch, long& not_unit) {
  double worst = 0;
  joint_mismatch = not_unit = 0;
  for (size_t i = 0; i < vertex.size(); ++i) {
    const auto& w = r.skin.vertex_weights[size_t(vertex[i])];
    const auto& j = r.skin.vertex_joints[size_t(vertex[i])];
    double sum = 0;
    for (int k = 0; k < 4; ++k) {
      worst = std::max(worst, double(std::abs(back.vertex_weights[i][k] - w[k])));
      joint_mismatch += w[k] > 0 ? back.vertex_joints[i][k] != j[k] : back.vertex_joints[i][k] != 0;
      sum += back.vertex_weights[i][k];
    }
    not_unit += std::abs(sum - 1) > 1e-6;
  }
  return worst;
}

Eigen::Vector3d rotated_about(const Eigen::Matrix3d& r, const Eigen::Vector3d& center, const Eigen::Vector3d& x) {
  return r * (x - center) + center;
}

}  // namespace

TEST_CASE("A rigged capsule written as .glb passes the skin rules and reads back with its joints and weights", "[gltf][gltf_skin]") {
  test_util::TempDir dir;
  const Rig r = capsule_rig();
  const std::string glb = dir / "capsule.glb";
  sdm::write_gltf_skinned(r.mesh, r.skin, glb);
  check_glb_structure(glb);
  const Glb g = read_glb(glb);
  check_skin_rules(g);
  // The joints: a chain of nodes translated from their parents, rooted at the root's position.
  const std::vector<int> joints = g.json["skins"][0]["joints"];
  CHECK(g.json["skins"][0]["skeleton"] == joints[0]);
  CHECK(g.json["nodes"][joints[1]]["translation"] == nlohmann::json({0.0, 0.0, 2.0}));
  CHECK(g.json["nodes"][joints[0]]["translation"] == nlohmann::json({0.0, 0.0, -2.0}));
  CHECK(g.json["nodes"][joints[2]]["name"] == "tip");

  sdm::GltfScene scene;
  const sdm::GltfSkin back = sdm::read_gltf_skin(glb, &scene);
  REQUIRE(back.joint_position.size() == 3);
  for (int k = 0; k < 3; ++k) CHECK((back.joint_position[size_t(k)] - r.skin.joint_position[size_t(k)]).norm() < 1e-6);
  CHECK(back.joint_parent == r.skin.joint_parent);
  CHECK(back.joint_name == r.skin.joint_name);
  REQUIRE(scene.soup.points.size() == r.mesh.n_vertices());
  REQUIRE(back.vertex_weights.size() == scene.soup.points.size());
  const std::vector<int> vertex = vertex_of_points(r.mesh, scene.soup.points);
  long joint_mismatch = 0, not_unit = 0;
  const double worst = weight_difference(r, back, vertex, joint_mismatch, not_unit);
  INFO("largest weight change " << worst);
  CHECK(worst < 1e-6);
  CHECK(joint_mismatch == 0);
  CHECK(not_unit == 0);
}

TEST_CASE("A rigged capsule posed by linear blend skinning from the file moves as its turned joint says", "[gltf][gltf_skin]") {
  test_util::TempDir dir;
  const Rig r = capsule_rig();
  sdm::write_gltf_skinned(r.mesh, r.skin, dir / "capsule.glb");
  const Glb g = read_glb(dir / "capsule.glb");
  const std::vector<Eigen::Vector3d> rest = pose(g, {});
  const auto& attr = g.json["meshes"][0]["primitives"][0]["attributes"];
  const std::vector<double> js = accessor_values(g, attr["JOINTS_0"]), ws = accessor_values(g, attr["WEIGHTS_0"]);
  const Eigen::Matrix3d quarter = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Vector3d middle(0, 0, kJointZ[1]), tip(0, 0, kJointZ[2]);
  // turned: the joint turned; what each joint's vertices become (the turned joint's subtree follows it)
  struct Case {
    int turned;
    std::array<bool, 3> follows;
  };
  for (const Case c : {Case{2, {false, false, true}}, Case{1, {false, true, true}}}) {
    const Eigen::Vector3d center = c.turned == 2 ? tip : middle;
    const std::vector<Eigen::Vector3d> posed = pose(g, {{c.turned, quarter}});
    double still = 0, turned = 0, blended = 0;
    long n_still = 0, n_turned = 0, n_blended = 0;
    for (size_t v = 0; v < posed.size(); ++v) {
      const Eigen::Vector3d x = rest[v];
      Eigen::Vector3d expected = Eigen::Vector3d::Zero();
      int single = -1;
      for (int k = 0; k < 4; ++k) {
        const int joint = int(js[4 * v + size_t(k)]);
        const double w = ws[4 * v + size_t(k)];
        expected += w * (c.follows[size_t(joint)] ? rotated_about(quarter, center, x) : x);
        if (w == 1.0) single = joint;
      }
      const double error = (posed[v] - expected).norm() / std::max(1.0, expected.norm());
      if (single >= 0 && !c.follows[size_t(single)]) still = std::max(still, (posed[v] - x).norm() / std::max(1.0, x.norm())), ++n_still;
      else if (single >= 0) turned = std::max(turned, error), ++n_turned;
      else blended = std::max(blended, error), ++n_blended;
    }
    INFO("joint " << c.turned << " turned: " << n_still << " vertices still (largest move " << still << "), " << n_turned
                  << " turned (largest error " << turned << "), " << n_blended << " blended (largest error " << blended << ")");
    CHECK(n_still > 100);
    CHECK(n_turned > 50);
    CHECK(n_blended > 50);
    CHECK(still < 1e-5);
    CHECK(turned < 1e-5);
    CHECK(blended < 1e-5);
  }
  // Unposed, the file's skinning leaves every vertex where POSITION puts it.
  const std::vector<double> x = accessor_values(g, attr["POSITION"]);
  double moved = 0;
  for (size_t v = 0; v < rest.size(); ++v) moved = std::max(moved, (rest[v] - Eigen::Vector3d(x[3 * v], x[3 * v + 1], x[3 * v + 2])).norm());
  CHECK(moved < 1e-6);
}

TEST_CASE("A forest of joints hangs under one untransformed skeleton node", "[gltf][gltf_skin]") {
  test_util::TempDir dir;
  Rig r = capsule_rig();
  r.skin.joint_position = {{0, 0, -1}, {0, 0, 1}};
  r.skin.joint_parent = {-1, -1};
  r.skin.joint_name.clear();
  for (auto v : r.mesh.vertices()) {
    const bool upper = r.mesh.point(v)[2] > 0;
    r.skin.vertex_joints[size_t(v.idx())] = {upper ? 1 : 0, 0, 0, 0};
    r.skin.vertex_weights[size_t(v.idx())] = {1, 0, 0, 0};
  }
  sdm::write_gltf_skinned(r.mesh, r.skin, dir / "forest.glb");
  check_glb_structure(dir / "forest.glb");
  const Glb g = read_glb(dir / "forest.glb");
  check_skin_rules(g);
  const auto& top = g.json["nodes"][g.json["skins"][0]["skeleton"].get<size_t>()];
  CHECK(top["name"] == "skeleton");
  CHECK(!top.contains("translation"));
  CHECK(top["children"] == g.json["skins"][0]["joints"]);
  CHECK(g.json["nodes"][g.json["skins"][0]["joints"][1].get<size_t>()]["name"] == "joint 1");
  const sdm::GltfSkin back = sdm::read_gltf_skin(dir / "forest.glb");
  CHECK(back.joint_parent == std::vector<int>{-1, -1});
  CHECK((back.joint_position[1] - Eigen::Vector3d(0, 0, 1)).norm() < 1e-6);
}

TEST_CASE("More than 256 joints are written as unsigned shorts and read back", "[gltf][gltf_skin]") {
  test_util::TempDir dir;
  Rig r = capsule_rig();
  const int n = 300;
  r.skin.joint_position.clear();
  r.skin.joint_parent.clear();
  r.skin.joint_name.clear();
  for (int k = 0; k < n; ++k) r.skin.joint_position.emplace_back(0, 0, -2 + 4.0 * k / (n - 1)), r.skin.joint_parent.push_back(k - 1);
  for (auto v : r.mesh.vertices()) {  // a ramp between the two joints around the vertex
    const double at = (r.mesh.point(v)[2] + 2) / 4 * (n - 1);
    const int k = std::min(int(at), n - 2);
    r.skin.vertex_joints[size_t(v.idx())] = {k, k + 1, 0, 0};
    r.skin.vertex_weights[size_t(v.idx())] = {float(k + 1 - at), float(at - k), 0, 0};
  }
  sdm::write_gltf_skinned(r.mesh, r.skin, dir / "long.glb");
  check_glb_structure(dir / "long.glb");
  check_skin_rules(read_glb(dir / "long.glb"));  // JOINTS_0 unsigned short among them
  sdm::GltfScene scene;
  const sdm::GltfSkin back = sdm::read_gltf_skin(dir / "long.glb", &scene);
  REQUIRE(back.joint_position.size() == size_t(n));
  CHECK((back.joint_position[299] - Eigen::Vector3d(0, 0, 2)).norm() < 1e-6);
  CHECK(back.joint_parent == r.skin.joint_parent);
  long joint_mismatch = 0, not_unit = 0;
  CHECK(weight_difference(r, back, vertex_of_points(r.mesh, scene.soup.points), joint_mismatch, not_unit) < 1e-6);
  CHECK(joint_mismatch == 0);
  CHECK(not_unit == 0);
}

TEST_CASE("Spot rigged with its texture: vertices split at uv seams carry their vertex's weights", "[gltf][gltf_skin]") {
  test_util::TempDir dir;
  Rig r{sdm::load_mesh(kSpot).mesh, {}};
  REQUIRE(r.mesh.has_halfedge_texcoords2D());
  double lo = INFINITY, hi = -INFINITY;
  for (auto v : r.mesh.vertices()) lo = std::min(lo, r.mesh.point(v)[2]), hi = std::max(hi, r.mesh.point(v)[2]);
  r.skin.joint_position = {{0, 0, lo}, {0, 0, hi}};
  r.skin.joint_parent = {-1, 0};
  for (auto v : r.mesh.vertices()) {  // a ramp along z: every vertex a blend of its own
    const float t = float((r.mesh.point(v)[2] - lo) / (hi - lo));
    r.skin.vertex_joints.push_back({0, 1, 0, 0});
    r.skin.vertex_weights.push_back({1 - t, t, 0, 0});
  }
  sdm::write_gltf_skinned(r.mesh, r.skin, dir / "spot.glb", kSpotTexture);
  check_glb_structure(dir / "spot.glb");
  const Glb g = read_glb(dir / "spot.glb");
  check_skin_rules(g);
  CHECK(g.json.at("images").size() == 1);
  const size_t written = g.json["accessors"][g.json["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"].get<size_t>()]["count"];
  INFO(written << " glTF vertices for " << r.mesh.n_vertices() << " mesh vertices");
  CHECK(written > r.mesh.n_vertices() + 50);  // seams split
  sdm::GltfScene scene;
  const sdm::GltfSkin back = sdm::read_gltf_skin(dir / "spot.glb", &scene);  // welded duplicates agree, or it throws
  REQUIRE(scene.soup.points.size() == r.mesh.n_vertices());
  CHECK(scene.texture.width > 0);
  long joint_mismatch = 0, not_unit = 0;
  CHECK(weight_difference(r, back, vertex_of_points(r.mesh, scene.soup.points), joint_mismatch, not_unit) < 1e-6);
  CHECK(joint_mismatch == 0);
  CHECK(not_unit == 0);
}

TEST_CASE("Bad skins are refused before anything is written", "[gltf][gltf_skin]") {
  test_util::TempDir dir;
  const std::string path = dir / "bad.glb";
  auto refused = [&](const std::function<void(Rig&)>& edit, const std::string& says) {
    Rig r = capsule_rig();
    edit(r);
    CHECK_THROWS_WITH(sdm::write_gltf_skinned(r.mesh, r.skin, path), Catch::Contains(says));
    CHECK(!std::ifstream(path).good());
  };
  refused([](Rig& r) { r.skin.joint_parent = {-1, 2, 1}; }, "cycle through joint");
  refused([](Rig& r) { r.skin.joint_parent = {-1, 0, 5}; }, "joint 2 has parent 5");
  refused([](Rig& r) { r.skin.joint_parent = {-1, 1, 1}; }, "joint 1 is its own parent");
  refused([](Rig& r) { r.skin.joint_parent = {-1, 0}; }, "joint_parent has 2 entries for 3 joints");
  refused([](Rig& r) { r.skin.vertex_weights.pop_back(); }, "vertex_weights has");
  refused([](Rig& r) { r.skin.joint_position.clear(); }, "no joints");
  refused([](Rig& r) { r.skin.joint_position[1].x() = NAN; }, "joint 1 has a position that is not finite");
  refused([](Rig& r) { r.skin.vertex_weights[7][1] = -0.25f; }, "vertex 7 has weight -0.25");
  refused([](Rig& r) { r.skin.vertex_weights[7][0] = NAN; }, "vertex 7 has weight nan");
  refused([](Rig& r) { r.skin.vertex_weights[7] = {0, 0, 0, 0}; }, "vertex 7 has all its weights 0");
  refused([](Rig& r) { r.skin.vertex_joints[7] = {3, 0, 0, 0}, r.skin.vertex_weights[7] = {1, 0, 0, 0}; }, "vertex 7 names joint 3");
  // Tidied, not refused: a joint named twice, weights not summing to 1.
  Rig r = capsule_rig();
  r.skin.vertex_joints[7] = {2, 2, 1, 0};
  r.skin.vertex_weights[7] = {0.5f, 0.5f, 1.0f, 0};
  sdm::write_gltf_skinned(r.mesh, r.skin, path);
  check_skin_rules(read_glb(path));
}

TEST_CASE("Malformed rigged glTF files are refused by name", "[gltf][gltf_skin][hostile]") {
  test_util::TempDir dir;
  const Rig r = capsule_rig();
  sdm::write_gltf_skinned(r.mesh, r.skin, dir / "good.glb");
  const Glb good = read_glb(dir / "good.glb");
  auto refused = [&](const std::function<void(nlohmann::json&)>& edit, const std::string& says) {
    nlohmann::json j = good.json;
    edit(j);
    test_util::write_file(dir / "bad.glb", make_glb(j, good.bin));
    CHECK_THROWS_WITH(sdm::read_gltf_skin(dir / "bad.glb"), Catch::Contains(says));
  };
  auto attribute = [](nlohmann::json& j, const char* name) -> nlohmann::json& {
    return j["accessors"][j["meshes"][0]["primitives"][0]["attributes"][name].get<size_t>()];
  };
  refused([](nlohmann::json& j) { j["skins"][0]["joints"].erase(2); }, "names joint 2 of a skin of 2 joints");
  refused([&](nlohmann::json& j) { attribute(j, "JOINTS_0")["count"] = 1000000000; }, "reaches outside its buffer");
  refused([&](nlohmann::json& j) { attribute(j, "WEIGHTS_0")["count"] = 10; }, "WEIGHTS_0 holds 10 elements");
  refused([](nlohmann::json& j) { j["meshes"][0]["primitives"][0]["attributes"].erase("WEIGHTS_0"); }, "without WEIGHTS_0");
  refused([](nlohmann::json& j) { j["accessors"][j["skins"][0]["inverseBindMatrices"].get<size_t>()]["count"] = 2; },
          "inverseBindMatrices hold 2 elements for 3 joints");
  refused([](nlohmann::json& j) { j["nodes"][0].erase("skin"); }, "holds a mesh without a skin");
  refused([](nlohmann::json& j) { j["meshes"][0]["primitives"][0]["attributes"]["JOINTS_1"] = 0; }, "more than 4 joints per vertex");
  // A file of plain write_gltf has no skin.
  sdm::write_gltf(r.mesh, dir / "plain.glb");
  CHECK_THROWS_AS(sdm::read_gltf_skin(dir / "plain.glb"), sdm::InputError);
}

TEST_CASE("Blender imports the rigged capsule as an armature that poses it", "[gltf][gltf_skin][blender]") {
  if (test_util::run_program("command", "-v blender").exit_code != 0) {
    WARN("Blender is not installed: the import check is skipped (scripts/install-deps.sh installs it)");
    return;
  }
  test_util::TempDir dir;
  const Rig r = capsule_rig();
  sdm::write_gltf_skinned(r.mesh, r.skin, dir / "capsule.glb");
  const std::string script = std::string(SDM_TEST_DATA) + "/../blender/check_rigged_gltf.py";
  const auto run = test_util::run_program("blender", "-b --factory-startup --python-exit-code 1 --python " + script + " -- " +
                                                         dir / "capsule.glb" + " tip");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const size_t at = run.output.find("RIGGED-GLTF ");
  REQUIRE(at != std::string::npos);
  const nlohmann::json j = nlohmann::json::parse(run.output.substr(at + 12, run.output.find('\n', at) - at - 12));
  REQUIRE(j.at("bones").size() == 3);
  std::map<std::string, nlohmann::json> bone;
  for (const auto& b : j["bones"]) bone[b.at("name")] = b;
  REQUIRE(bone.count("root") + bone.count("middle") + bone.count("tip") == 3);
  CHECK(bone["middle"]["parent"] == "root");
  CHECK(bone["tip"]["parent"] == "middle");
  for (int k = 0; k < 3; ++k) {
    const std::vector<double> head = bone[r.skin.joint_name[size_t(k)]]["head"];
    CHECK((Eigen::Vector3d(head[0], head[1], head[2]) - r.skin.joint_position[size_t(k)]).norm() < 1e-5);
  }
  CHECK(j.at("vertices").get<size_t>() >= r.mesh.n_vertices());
  CHECK(j.at("ungrouped") == 0);
  CHECK(j.at("pose_error").get<double>() < 1e-5);
}

TEST_CASE("Rigged glTF files with a skin value mutated are read or refused with InputError", "[gltf][gltf_skin][hostile][fuzz]") {
  test_util::TempDir dir;
  const Rig r = capsule_rig();
  sdm::write_gltf_skinned(r.mesh, r.skin, dir / "seed.glb");
  const Glb seed = read_glb(dir / "seed.glb");
  // Where a skin can go wrong: its joints, skeleton and matrices, the joint nodes' tree and
  // translations, the skinned node, and the influence accessors and their views.
  const auto& attr = seed.json["meshes"][0]["primitives"][0]["attributes"];
  const int ibm = seed.json["skins"][0]["inverseBindMatrices"];
  std::vector<nlohmann::json::json_pointer> targets = {
      nlohmann::json::json_pointer("/skins/0/joints/1"), nlohmann::json::json_pointer("/skins/0/skeleton"),
      nlohmann::json::json_pointer("/skins/0/inverseBindMatrices"), nlohmann::json::json_pointer("/nodes/0/skin"),
      nlohmann::json::json_pointer("/nodes/1/children/0"), nlohmann::json::json_pointer("/nodes/2/children/0"),
      nlohmann::json::json_pointer("/nodes/3/translation/2"), nlohmann::json::json_pointer("/scenes/0/nodes/1"),
      nlohmann::json::json_pointer("/meshes/0/primitives/0/attributes/JOINTS_0"),
      nlohmann::json::json_pointer("/meshes/0/primitives/0/attributes/WEIGHTS_0")};
  for (const int a : {attr["JOINTS_0"].get<int>(), attr["WEIGHTS_0"].get<int>(), ibm})
    for (const char* key : {"count", "componentType", "type", "byteOffset", "bufferView", "normalized"})
      targets.emplace_back("/accessors/" + std::to_string(a) + "/" + key);
  const std::vector<nlohmann::json> values = {0, 1, 2, 3, -1, 5121, 5123, 5126, "VEC4", "MAT4", "SCALAR", 4294967296LL, 1e308, nullptr, true};
  std::mt19937 rng(7);
  long refused = 0, read = 0;
  for (int i = 0; i < 400; ++i) {
    nlohmann::json j = seed.json;
    for (int m = 0; m < 1 + int(rng() % 2); ++m) j[targets[rng() % targets.size()]] = values[rng() % values.size()];
    test_util::write_file(dir / "m.glb", make_glb(j, seed.bin));
    try {
      sdm::read_gltf_skin(dir / "m.glb");
      ++read;
    } catch (const sdm::InputError&) {
      ++refused;
    } catch (const std::exception& e) {
      FAIL("mutation " << i << " threw " << e.what() << "\n" << j.dump());
    }
  }
  INFO(read << " read, " << refused << " refused");
  CHECK(refused > 100);
}
