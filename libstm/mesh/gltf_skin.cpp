#include "libstm/mesh/gltf_skin.h"

#include "libstm/core/errors.h"
#include "libstm/mesh/gltf_io_internal.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>

namespace sdm {
namespace {

using gltf_internal::AccessorView;

// glTF's JOINTS_0 is unsigned short at most: joint indices up to 65535.
constexpr size_t kMaxJoints = 65536;

// The first element of a cycle of `parent` (each element's parent, -1 for a root), or -1 when every
// element reaches a root.
int on_cycle(const std::vector<int>& parent) {
  std::vector<char> state(parent.size(), 0);  // 0 unseen, 1 on the current walk, 2 reaches a root
  for (size_t j = 0; j < parent.size(); ++j) {
    std::vector<int> walk;
    int k = int(j);
    while (k >= 0 && state[size_t(k)] == 0) state[size_t(k)] = 1, walk.push_back(k), k = parent[size_t(k)];
    if (k >= 0 && state[size_t(k)] == 1) return k;
    for (int w : walk) state[size_t(w)] = 2;
  }
  return -1;
}

// Throws InputError unless the parents name joints and reach a root from every joint.
void check_parents(const std::vector<int>& parent, const std::string& what) {
  const int n = int(parent.size());
  for (int j = 0; j < n; ++j) {
    if (parent[j] < -1 || parent[j] >= n)
      throw InputError(what + ": joint " + std::to_string(j) + " has parent " + std::to_string(parent[j]) + ", neither a joint (there are " +
                       std::to_string(n) + ") nor -1 for a root");
    if (parent[j] == j) throw InputError(what + ": joint " + std::to_string(j) + " is its own parent");
  }
  const int k = on_cycle(parent);
  if (k >= 0) throw InputError(what + ": the joint parents form a cycle through joint " + std::to_string(k) + " (they must form a tree or a forest)");
}

void check_skin(const Mesh& mesh, const GltfSkin& skin, const std::string& what) {
  const size_t n = skin.joint_position.size(), v = mesh.n_vertices();
  if (n == 0) throw InputError(what + ": the skin has no joints");
  if (n > kMaxJoints) throw InputError(what + ": " + std::to_string(n) + " joints (glTF's joint indices reach 65535 at most)");
  auto size = [&](size_t got, size_t want, const std::string& name, const std::string& per) {
    if (got != want)
      throw InputError(what + ": " + name + " has " + std::to_string(got) + " entries for " + std::to_string(want) + " " + per);
  };
  size(skin.joint_parent.size(), n, "joint_parent", "joints");
  if (!skin.joint_name.empty()) size(skin.joint_name.size(), n, "joint_name", "joints");
  size(skin.vertex_joints.size(), v, "vertex_joints", "mesh vertices");
  size(skin.vertex_weights.size(), v, "vertex_weights", "mesh vertices");
  for (size_t j = 0; j < n; ++j)
    if (!skin.joint_position[j].allFinite()) throw InputError(what + ": joint " + std::to_string(j) + " has a position that is not finite");
  if (!skin.joint_pose_rotation.empty() || !skin.joint_pose_position.empty()) {
    size(skin.joint_pose_rotation.size(), n, "joint_pose_rotation", "joints");
    size(skin.joint_pose_position.size(), n, "joint_pose_position", "joints");
    for (size_t j = 0; j < n; ++j)
      if (!skin.joint_pose_rotation[j].coeffs().allFinite() || !(skin.joint_pose_rotation[j].norm() > 0) || !skin.joint_pose_position[j].allFinite())
        throw InputError(what + ": joint " + std::to_string(j) + " has a pose that is not finite");
  }
  check_parents(skin.joint_parent, what);
  for (size_t i = 0; i < v; ++i) {
    float sum = 0;
    for (int k = 0; k < 4; ++k) {
      const float w = skin.vertex_weights[i][k];
      const int j = skin.vertex_joints[i][k];
      if (!(w >= 0) || !std::isfinite(w))
        throw InputError(what + ": vertex " + std::to_string(i) + " has weight " + number(w) + " (weights must be finite and >= 0)");
      if (w > 0 && (j < 0 || size_t(j) >= n))
        throw InputError(what + ": vertex " + std::to_string(i) + " names joint " + std::to_string(j) + " (there are " + std::to_string(n) + ")");
      sum += w;
    }
    if (!(sum > 0)) throw InputError(what + ": vertex " + std::to_string(i) + " has all its weights 0 (every vertex needs a joint)");
  }
}

// One vertex's influences as written (gltf_skin.h: duplicates merged, zero slots joint 0, the float
// sum in slot order 1, as the validator adds them).
struct Influence {
  std::array<int, 4> joint{};
  std::array<float, 4> weight{};
};

Influence tidy(const std::array<int, 4>& joints, const std::array<float, 4>& weights) {
  std::array<double, 4> w{};
  Influence out;
  for (int k = 0; k < 4; ++k) {
    if (!(weights[k] > 0)) continue;
    int slot = k;
    for (int m = 0; m < k; ++m)
      if (w[m] > 0 && out.joint[m] == joints[k]) slot = m;
    w[slot] += weights[k];
    out.joint[slot] = joints[k];
  }
  const double sum = w[0] + w[1] + w[2] + w[3];
  int big = 0;
  for (int k = 0; k < 4; ++k) {
    out.weight[k] = float(w[k] / sum);
    if (out.weight[k] > out.weight[big]) big = k;
  }
  for (int step = 0; step < 64; ++step) {
    float s = 0;
    for (int k = 0; k < 4; ++k) s = s + out.weight[k];  // float arithmetic, slot by slot
    if (s == 1.0f) break;
    out.weight[big] = std::nextafter(out.weight[big], s < 1.0f ? 2.0f : 0.0f);
  }
  return out;
}

// Adds the joint nodes after the model's nodes (joint j becomes node first + j), the "skeleton"
// node over the roots when there are several, and the skin with its inverse bind matrices; the
// scene gets the root node. Returns the skin's index.
int add_skin(tinygltf::Model& m, const GltfSkin& skin) {
  const int n = int(skin.joint_position.size()), first = int(m.nodes.size());
  std::vector<int> roots;
  for (int j = 0; j < n; ++j) {
    tinygltf::Node node;
    node.name = skin.joint_name.empty() ? "joint " + std::to_string(j) : skin.joint_name[j];
    const int p = skin.joint_parent[j];
    if (skin.joint_pose_rotation.empty()) {
      const Eigen::Vector3d t = skin.joint_position[j] - (p >= 0 ? skin.joint_position[p] : Eigen::Vector3d::Zero());
      node.translation = {t.x(), t.y(), t.z()};
    } else {  // local = parent's global^-1 * own global, globals x -> R x + position
      const Eigen::Quaterniond rp = p >= 0 ? skin.joint_pose_rotation[p].normalized() : Eigen::Quaterniond::Identity();
      const Eigen::Vector3d pp = p >= 0 ? skin.joint_pose_position[p] : Eigen::Vector3d::Zero();
      const Eigen::Vector3d t = rp.conjugate() * (skin.joint_pose_position[j] - pp);
      const Eigen::Quaterniond r = rp.conjugate() * skin.joint_pose_rotation[j].normalized();
      node.translation = {t.x(), t.y(), t.z()};
      if (r.angularDistance(Eigen::Quaterniond::Identity()) > 0) node.rotation = {r.x(), r.y(), r.z(), r.w()};
    }
    m.nodes.push_back(node);
    if (p < 0) roots.push_back(j);
  }
  for (int j = 0; j < n; ++j)
    if (skin.joint_parent[j] >= 0) m.nodes[first + skin.joint_parent[j]].children.push_back(first + j);
  tinygltf::Skin s;
  s.name = "sdm_skeleton";
  if (roots.size() == 1) {
    s.skeleton = first + roots[0];
  } else {
    tinygltf::Node top;
    top.name = "skeleton";
    for (int r : roots) top.children.push_back(first + r);
    m.nodes.push_back(top);
    s.skeleton = int(m.nodes.size()) - 1;
  }
  m.scenes[0].nodes.push_back(s.skeleton);
  std::vector<float> ibm(16 * size_t(n), 0.0f);
  for (int j = 0; j < n; ++j) {
    float* a = ibm.data() + 16 * size_t(j);  // column-major
    a[0] = a[5] = a[10] = a[15] = 1.0f;
    for (int c = 0; c < 3; ++c) a[12 + c] = float(-skin.joint_position[j][c]);
    s.joints.push_back(first + j);
  }
  s.inverseBindMatrices = gltf_internal::add_accessor(m, gltf_internal::add_view(m, ibm.data(), 4 * ibm.size(), 0),
                                                      TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_MAT4, size_t(n));
  m.skins.push_back(s);
  return int(m.skins.size()) - 1;
}

// JOINTS_0 and WEIGHTS_0 of the written vertices onto the model's only primitive.
void add_influences(gltf_internal::MeshModel& mm, const GltfSkin& skin) {
  std::vector<Influence> tidied(skin.vertex_joints.size());
  for (size_t i = 0; i < tidied.size(); ++i) tidied[i] = tidy(skin.vertex_joints[i], skin.vertex_weights[i]);
  const size_t count = mm.source_vertex.size();
  std::vector<uint8_t> joints8;
  std::vector<uint16_t> joints16;
  std::vector<float> weights;
  const bool bytes = skin.joint_position.size() <= 256;
  for (int v : mm.source_vertex)
    for (int k = 0; k < 4; ++k) {
      if (bytes) joints8.push_back(uint8_t(tidied[size_t(v)].joint[k]));
      else joints16.push_back(uint16_t(tidied[size_t(v)].joint[k]));
      weights.push_back(tidied[size_t(v)].weight[k]);
    }
  tinygltf::Model& m = mm.model;
  tinygltf::Primitive& p = m.meshes[0].primitives[0];
  const int joint_view = bytes ? gltf_internal::add_view(m, joints8.data(), joints8.size(), TINYGLTF_TARGET_ARRAY_BUFFER)
                               : gltf_internal::add_view(m, joints16.data(), 2 * joints16.size(), TINYGLTF_TARGET_ARRAY_BUFFER);
  p.attributes["JOINTS_0"] = gltf_internal::add_accessor(
      m, joint_view, bytes ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE : TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4, count);
  p.attributes["WEIGHTS_0"] =
      gltf_internal::add_accessor(m, gltf_internal::add_view(m, weights.data(), 4 * weights.size(), TINYGLTF_TARGET_ARRAY_BUFFER),
                                  TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, count);
}

}  // namespace

void write_gltf_skinned(const Mesh& mesh, const GltfSkin& skin, const std::string& path, const std::string& texture_png) {
  check_skin(mesh, skin, "cannot write rigged glTF " + path);
  gltf_internal::MeshModel mm = gltf_internal::mesh_model(mesh, path, texture_png);
  add_influences(mm, skin);
  mm.model.nodes[0].skin = add_skin(mm.model, skin);
  gltf_internal::save_model(mm.model, path);
}

namespace {

// Collects the influences of the skinned primitives onto the welded points (read_gltf_skin).
struct InfluenceReader {
  const tinygltf::Model& model;
  std::string what;
  int skin = -1;
  std::vector<std::array<int, 4>> joints;
  std::vector<std::array<float, 4>> weights;
  std::vector<char> seen;  // per point

  // The skin of the node holding a primitive, checked to be the one skin read.
  size_t skin_joints(int node) {
    const int s = node >= 0 ? model.nodes[size_t(node)].skin : -1;
    if (s < 0)
      throw InputError(what + ": " + (node >= 0 ? "node " + std::to_string(node) : std::string("a mesh outside every node")) +
                       " holds a mesh without a skin (every mesh must be skinned to read a rig)");
    if (s >= int(model.skins.size())) throw InputError(what + ": node " + std::to_string(node) + " names skin " + std::to_string(s) + ", which does not exist");
    if (skin >= 0 && s != skin) throw InputError(what + ": its meshes are skinned by different skins (" + std::to_string(skin) + " and " + std::to_string(s) + "); sdm reads one");
    skin = s;
    return model.skins[size_t(s)].joints.size();
  }

  AccessorView attribute(const tinygltf::Primitive& p, const std::string& name, size_t count) {
    const auto it = p.attributes.find(name);
    if (it == p.attributes.end()) throw InputError(what + ": a skinned primitive without " + name);
    const AccessorView a(model, it->second, what);
    if (a.count() != count || a.components() != 4)
      throw InputError(what + ": " + name + " holds " + std::to_string(a.count()) + " elements of " + std::to_string(a.components()) +
                       " components where POSITION has " + std::to_string(count) + " vertices (VEC4 each)");
    const tinygltf::Accessor& acc = model.accessors[size_t(it->second)];
    const int t = acc.componentType;
    const bool ok = name == "JOINTS_0" ? (t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) && !acc.normalized
                                       : t == TINYGLTF_COMPONENT_TYPE_FLOAT || ((t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                                                                 t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) && acc.normalized);
    if (!ok) throw InputError(what + ": " + name + " has component type " + std::to_string(t) + ", which glTF does not allow there");
    return a;
  }

  void operator()(int node, const tinygltf::Primitive& p, const std::vector<int>& point) {
    const size_t n = skin_joints(node);
    if (p.attributes.count("JOINTS_1") || p.attributes.count("WEIGHTS_1"))
      throw InputError(what + ": more than 4 joints per vertex (JOINTS_1); sdm reads 4");
    const AccessorView J = attribute(p, "JOINTS_0", point.size()), W = attribute(p, "WEIGHTS_0", point.size());
    for (int x : point)
      if (size_t(x) >= seen.size()) seen.resize(size_t(x) + 1, 0), joints.resize(seen.size()), weights.resize(seen.size());
    for (size_t i = 0; i < point.size(); ++i) {
      std::array<int, 4> j{};
      std::array<float, 4> w{};
      double sum = 0;
      for (int k = 0; k < 4; ++k) {
        const double jk = J.get(i, k), wk = W.get(i, k);
        if (jk >= double(n)) throw InputError(what + ": vertex " + std::to_string(i) + " names joint " + number(jk) + " of a skin of " + std::to_string(n) + " joints");
        if (!(wk >= 0) || !std::isfinite(wk)) throw InputError(what + ": vertex " + std::to_string(i) + " has weight " + number(wk));
        j[k] = wk > 0 ? int(jk) : 0, w[k] = float(wk), sum += wk;
      }
      if (!(sum > 0)) throw InputError(what + ": vertex " + std::to_string(i) + " has all its weights 0");
      if (std::abs(sum - 1) > 1e-6)
        for (float& x : w) x = float(x / sum);
      store(size_t(point[i]), j, w);
    }
  }

  // The first glTF vertex welded at a point gives its influences; the others must agree.
  void store(size_t x, const std::array<int, 4>& j, const std::array<float, 4>& w) {
    if (!seen[x]) {
      seen[x] = 1, joints[x] = j, weights[x] = w;
      return;
    }
    std::map<int, double> d;
    for (int k = 0; k < 4; ++k) d[joints[x][k]] += weights[x][k], d[j[k]] -= w[k];
    for (const auto& [joint, diff] : d)
      if (std::abs(diff) > 1e-4)
        throw InputError(what + ": vertices at one position (point " + std::to_string(x) + ") give joint " + std::to_string(joint) +
                         " weights differing by " + number(std::abs(diff)) + " (they would tear apart when posed)");
  }
};

// Each node's parent (-1 for none).
std::vector<int> node_parents(const tinygltf::Model& m, const std::string& what) {
  std::vector<int> parent(m.nodes.size(), -1);
  for (size_t i = 0; i < m.nodes.size(); ++i)
    for (int c : m.nodes[i].children) {
      if (c < 0 || size_t(c) >= m.nodes.size() || parent[size_t(c)] >= 0)
        throw InputError(what + ": node " + std::to_string(i) + " has child " + std::to_string(c) + ", missing or another node's child");
      parent[size_t(c)] = int(i);
    }
  const int k = on_cycle(parent);
  if (k >= 0) throw InputError(what + ": its node tree has a cycle through node " + std::to_string(k));
  return parent;
}

// The joints of skin s: parents from the node tree, rest positions from the inverse bind matrices
// (or the nodes' global transforms), names from the nodes.
void read_joints(const tinygltf::Model& m, int s, const std::string& what, GltfSkin& out) {
  const tinygltf::Skin& skin = m.skins[size_t(s)];
  const std::vector<int> parent = node_parents(m, what);
  std::map<int, int> joint_of;  // node -> joint
  for (size_t j = 0; j < skin.joints.size(); ++j) {
    const int node = skin.joints[j];
    if (node < 0 || size_t(node) >= m.nodes.size()) throw InputError(what + ": skin joint " + std::to_string(j) + " names missing node " + std::to_string(node));
    if (!joint_of.emplace(node, int(j)).second) throw InputError(what + ": node " + std::to_string(node) + " is a joint of the skin twice");
  }
  std::unique_ptr<AccessorView> ibm;
  if (skin.inverseBindMatrices >= 0) {
    ibm = std::make_unique<AccessorView>(m, skin.inverseBindMatrices, what);
    if (ibm->count() != skin.joints.size() || ibm->components() != 16 ||
        m.accessors[size_t(skin.inverseBindMatrices)].componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
      throw InputError(what + ": the skin's inverseBindMatrices hold " + std::to_string(ibm->count()) + " elements for " +
                       std::to_string(skin.joints.size()) + " joints (float MAT4 each)");
  }
  for (size_t j = 0; j < skin.joints.size(); ++j) {
    const int node = skin.joints[j];
    int p = parent[size_t(node)];
    while (p >= 0 && !joint_of.count(p)) p = parent[size_t(p)];
    out.joint_parent.push_back(p >= 0 ? joint_of[p] : -1);
    out.joint_name.push_back(m.nodes[size_t(node)].name);
    Eigen::Affine3d rest = Eigen::Affine3d::Identity();
    if (ibm) {
      Eigen::Matrix4d a;
      for (int k = 0; k < 16; ++k) a(k % 4, k / 4) = ibm->get(j, k);  // column-major
      if (!a.allFinite() || !(std::abs(a.determinant()) > 1e-12))
        throw InputError(what + ": inverse bind matrix " + std::to_string(j) + " is not invertible");
      rest.matrix() = a.inverse();
    } else {
      for (int k = node; k >= 0; k = parent[size_t(k)]) rest = gltf_internal::node_transform(m.nodes[size_t(k)]) * rest;
    }
    out.joint_position.push_back(rest.translation());
  }
}

}  // namespace

GltfSkin read_gltf_skin(const std::string& path, GltfScene* scene) {
  const tinygltf::Model model = gltf_internal::load_model(path);
  InfluenceReader influences{model, "glTF " + path, -1, {}, {}, {}};
  GltfScene read = gltf_internal::read_model(model, path, std::ref(influences));
  if (influences.skin < 0) throw InputError("glTF " + path + " has no skinned mesh");
  GltfSkin out;
  read_joints(model, influences.skin, "glTF " + path, out);
  if (influences.seen.size() != read.soup.points.size() || std::count(influences.seen.begin(), influences.seen.end(), 0))
    throw InputError("glTF " + path + ": points without joints");  // every primitive read is skinned: not reached
  out.vertex_joints = std::move(influences.joints);
  out.vertex_weights = std::move(influences.weights);
  if (scene) *scene = std::move(read);
  return out;
}

}  // namespace sdm
