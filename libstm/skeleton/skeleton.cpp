#include "libstm/skeleton/skeleton.h"

#include "libstm/core/atomic_file.h"
#include "libstm/core/errors.h"
#include "libstm/core/input_file.h"
#include "libstm/core/json_int.h"
#include "libstm/core/limits.h"
#include "libstm/core/union_find.h"

#include <cmath>
#include <set>
#include <sstream>

namespace sdm {

std::vector<std::vector<int>> Skeleton::adjacency() const {
  std::vector<std::vector<int>> adj(nodes.size());
  for (const auto& e : edges) {
    adj[e[0]].push_back(e[1]);
    adj[e[1]].push_back(e[0]);
  }
  return adj;
}

std::vector<int> Skeleton::degrees() const {
  std::vector<int> d(nodes.size(), 0);
  for (const auto& e : edges) d[e[0]]++, d[e[1]]++;
  return d;
}

int Skeleton::components() const {
  UnionFind sets(nodes.size());
  for (const auto& e : edges) sets.unite(e[0], e[1]);
  return sets.count();
}

int Skeleton::cycles() const { return int(edges.size()) - int(nodes.size()) + components(); }

int Skeleton::branch_nodes() const {
  int n = 0;
  for (int d : degrees()) n += d >= 3;
  return n;
}

int Skeleton::end_nodes() const {
  int n = 0;
  for (int d : degrees()) n += d == 1;
  return n;
}

int restrict_to_vertices(Skeleton& s, int vertices) {
  s.vertex_node.resize(size_t(std::max(0, vertices)));
  const size_t k = s.nodes.size();
  std::vector<int> owned(k, 0);
  for (int n : s.vertex_node) ++owned[size_t(n)];
  std::vector<std::set<int>> adj(k);
  for (const auto& e : s.edges) adj[size_t(e[0])].insert(e[1]), adj[size_t(e[1])].insert(e[0]);
  std::vector<char> alive(k, 1);
  int removed = 0;
  for (;;) {
    // The unowned node of least degree first: ends go before the chains they hang from.
    int u = -1;
    for (size_t a = 0; a < k; ++a)
      if (alive[a] && !owned[a] && (u < 0 || adj[a].size() < adj[size_t(u)].size())) u = int(a);
    if (u < 0) break;
    std::vector<int> nb(adj[size_t(u)].begin(), adj[size_t(u)].end());
    for (int x : nb) adj[size_t(x)].erase(u);
    adj[size_t(u)].clear();
    alive[size_t(u)] = 0;
    ++removed;
    if (nb.size() < 2) continue;
    // The nearest neighbour takes the node's other edges (for degree 2, simply joins the two).
    int w = nb[0];
    for (int x : nb)
      if ((s.nodes[size_t(x)] - s.nodes[size_t(u)]).squaredNorm() < (s.nodes[size_t(w)] - s.nodes[size_t(u)]).squaredNorm()) w = x;
    for (int x : nb)
      if (x != w) adj[size_t(x)].insert(w), adj[size_t(w)].insert(x);
  }
  if (!removed) return 0;
  std::vector<int> index(k, -1);
  Skeleton out;
  for (size_t a = 0; a < k; ++a)
    if (alive[a]) index[a] = int(out.nodes.size()), out.nodes.push_back(s.nodes[a]);
  for (size_t a = 0; a < k; ++a)
    for (int b : adj[a])
      if (int(a) < b) out.edges.push_back({index[a], index[size_t(b)]});
  out.vertex_node.reserve(s.vertex_node.size());
  for (int n : s.vertex_node) out.vertex_node.push_back(index[size_t(n)]);
  s = std::move(out);
  return removed;
}

nlohmann::json skeleton_to_json(const Skeleton& s) {
  nlohmann::json j;
  j["format"] = "sdm-skeleton";
  j["version"] = 1;
  j["nodes"] = nlohmann::json::array();
  for (const auto& n : s.nodes) j["nodes"].push_back({n.x(), n.y(), n.z()});
  j["edges"] = nlohmann::json::array();
  for (const auto& e : s.edges) j["edges"].push_back({e[0], e[1]});
  j["vertex_node"] = s.vertex_node;
  return j;
}

Skeleton skeleton_from_json(const nlohmann::json& j) {
  Skeleton s;
  try {
    if (j.contains("skeleton")) return skeleton_from_json(j.at("skeleton"));  // a layout holds one
    for (const auto& n : j.at("nodes")) s.nodes.emplace_back(n.at(0).get<double>(), n.at(1).get<double>(), n.at(2).get<double>());
    for (const auto& e : j.at("edges")) s.edges.push_back({json_int(e.at(0)), json_int(e.at(1))});
    s.vertex_node = json_ints(j.at("vertex_node"));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("not a valid skeleton: ") + e.what());
  }
  const int n = int(s.nodes.size());
  for (size_t i = 0; i < s.edges.size(); ++i)
    for (int k : s.edges[i])
      if (k < 0 || k >= n)
        throw InputError("not a valid skeleton: edge " + std::to_string(i) + " names node " + std::to_string(k) + " of " +
                         std::to_string(n));
  for (size_t i = 0; i < s.vertex_node.size(); ++i)
    if (s.vertex_node[i] < 0 || s.vertex_node[i] >= n)
      throw InputError("not a valid skeleton: vertex " + std::to_string(i) + " maps to node " +
                       std::to_string(s.vertex_node[i]) + " of " + std::to_string(n));
  check_skeleton_geometry(s);
  return s;
}

void check_skeleton_geometry(const Skeleton& s) {
  for (size_t i = 0; i < s.nodes.size(); ++i) {
    const Eigen::Vector3d& p = s.nodes[i];
    if (!p.allFinite())
      throw InputError("not a valid skeleton: node " + std::to_string(i) + " has NaN or infinite coordinates");
    if (p.cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw InputError("not a valid skeleton: node " + std::to_string(i) + " lies at " + number(p.cwiseAbs().maxCoeff()) +
                       ", beyond the coordinate range of a mesh (+-3.4e38, single precision)");
  }
  for (size_t i = 0; i < s.edges.size(); ++i) {
    const int a = s.edges[i][0], b = s.edges[i][1];
    if (a == b) throw InputError("not a valid skeleton: edge " + std::to_string(i) + " joins node " + std::to_string(a) + " to itself");
    // Coincident ends leave the segment without a direction: no capsule, no frame, no rays.
    const Eigen::Vector3d& p = s.nodes[a];
    const Eigen::Vector3d& q = s.nodes[b];
    if ((p - q).norm() <= 1e-12 * std::max(p.norm(), q.norm()))
      throw InputError("not a valid skeleton: edge " + std::to_string(i) + " joins nodes " + std::to_string(a) + " and " +
                       std::to_string(b) + ", which coincide (a segment needs a length). Fix: extract the skeleton again");
  }
}

void write_skeleton_json(const Skeleton& s, const std::string& path) {
  write_text_file(path, skeleton_to_json(s).dump() + "\n");
}

Skeleton read_skeleton_json(const std::string& path, const ReadBudget& budget) {
  const std::string text = read_input_file(path, "skeleton", kMaxJsonFileBytes, budget, kJsonBytesPerFileByte);
  nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded()) throw InputError("cannot read skeleton " + path + ": not JSON");
  try {
    return skeleton_from_json(j);
  } catch (const InputError& e) {
    throw InputError("skeleton " + path + ": " + e.what());
  }
}

void write_skeleton_obj(const Skeleton& s, const std::string& path) {
  std::ostringstream o;
  o.precision(17);
  o << "# sdm skeleton: " << s.nodes.size() << " nodes, " << s.edges.size() << " edges\n";
  for (const auto& n : s.nodes) o << "v " << n.x() << ' ' << n.y() << ' ' << n.z() << '\n';
  for (const auto& e : s.edges) o << "l " << e[0] + 1 << ' ' << e[1] + 1 << '\n';
  write_text_file(path, o.str());
}

}  // namespace sdm
