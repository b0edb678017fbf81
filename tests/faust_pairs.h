#pragma once
// FAUST pairs for the registration tests (tr_reg_007 and tr_reg_024 of ../shared/models/humans: the
// same connectivity, so vertex i of one corresponds to vertex i of the other): the node guesses a
// correct skeleton match gives, the targets the tests build (turned and scaled, an arm bent at the
// elbow), and the correspondence error against the ground truth.
#include "libstm/core/image.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/registration/carry_skeleton.h"
#include "libstm/skeleton/skeleton.h"

#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace faust {

#ifdef SDM_HUMANS
inline std::string humans_dir() { return SDM_HUMANS; }
#else
// The repository's sibling ../shared (tests/data is two levels below the repository root).
inline std::string humans_dir() { return std::string(SDM_TEST_DATA) + "/../../../shared/models/humans"; }
#endif

inline bool have(const std::string& name) { return std::ifstream(humans_dir() + "/" + name).good(); }

inline std::vector<Eigen::Vector3d> points_of(const sdm::Mesh& m) {
  std::vector<Eigen::Vector3d> p;
  for (auto v : m.vertices()) p.push_back(sdm::point(m, v));
  return p;
}

// Per node of the source's skeleton, the centroid of the target vertices with the indices of the
// source vertices it owns: where a correct match of the skeletons puts it.
inline std::vector<Eigen::Vector3d> true_guess(const sdm::Skeleton& s, const sdm::Mesh& target) {
  std::vector<Eigen::Vector3d> sum(s.nodes.size(), Eigen::Vector3d::Zero());
  std::vector<int> n(s.nodes.size(), 0);
  for (size_t v = 0; v < s.vertex_node.size(); ++v) sum[s.vertex_node[v]] += sdm::point(target, target.vertex_handle(int(v))), ++n[s.vertex_node[v]];
  for (size_t k = 0; k < sum.size(); ++k) sum[k] /= std::max(n[k], 1);
  return sum;
}

struct Error {
  double mean = 0, p90 = 0, beyond5 = 0;  // % of the source's diagonal; share of vertices in %
};

// The file `sdm transfer --correspondence FILE.txt` writes, read back: per target vertex, in order,
// the source face and the barycentric coordinates on it ('#' lines skipped). REQUIREs every line
// to hold four numbers.
inline std::vector<sdm::SourcePoint> read_correspondence(const std::string& path) {
  std::ifstream in(path);
  std::vector<sdm::SourcePoint> out;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream l(line);
    sdm::SourcePoint p;
    l >> p.face >> p.barycentric[0] >> p.barycentric[1] >> p.barycentric[2];
    REQUIRE(l);
    out.push_back(p);
  }
  return out;
}

// The point of `source` a correspondence entry names: its face's corners (fv_range order) blended.
inline Eigen::Vector3d point_under(const sdm::Mesh& source, const sdm::SourcePoint& q) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  int c = 0;
  for (auto v : source.fv_range(source.face_handle(q.face))) p += q.barycentric[c++] * sdm::point(source, v);
  return p;
}

// For every target vertex j, the distance between the source point under it and source vertex j.
inline Error correspondence_error(const sdm::Mesh& source, const std::vector<sdm::SourcePoint>& under) {
  const double diag = sdm::bounding_box_diagonal(source);
  std::vector<double> e;
  for (size_t j = 0; j < under.size(); ++j) {
    e.push_back(100 * (point_under(source, under[j]) - sdm::point(source, source.vertex_handle(int(j)))).norm() / diag);
  }
  Error r;
  for (double x : e) r.mean += x, r.beyond5 += x > 5;
  r.mean /= double(e.size()), r.beyond5 *= 100.0 / double(e.size());
  std::sort(e.begin(), e.end());
  r.p90 = e[size_t(0.9 * double(e.size()))];
  return r;
}

// The human `name` with uv from a planar projection and a texture whose red grows with u, written
// as `obj` (with its MTL) and `png`: a source as `sdm transfer` reads it. Returns the mesh written.
inline sdm::Mesh write_textured(const std::string& name, const std::string& obj, const std::string& png) {
  const sdm::Mesh a = sdm::with_planar_uv(sdm::load_mesh(humans_dir() + "/" + name).mesh);
  sdm::Image tex(32, 32, 4, 255);
  for (int i = 0; i < 32 * 32; ++i) tex.pixels[4 * i] = uint8_t(8 * (i % 32));
  sdm::write_png(tex, png);
  sdm::write_mesh(a, obj, png);
  return a;
}

// The target turned 180 degrees about its vertical (y) axis and scaled by `scale`.
inline sdm::Mesh turned_scaled(const sdm::Mesh& m, double scale) {
  sdm::Mesh out = m;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (auto v : out.vertices()) {
    const Eigen::Vector3d p = scale * (R * sdm::point(m, v));
    out.set_point(v, sdm::Mesh::Point(p.x(), p.y(), p.z()));
  }
  return out;
}

// One arm of `m` bent a further `degrees` at its elbow. The arm is found on the skeleton `s` of the
// source (its vertex_node indexes m's vertices too): of the ends above the two lowest (the feet), the
// one with the longest chain to its junction; the elbow is the chain's node at `at` of its length
// from the junction, in m at the centroid of the vertices it owns (true_guess). Vertices beyond the
// elbow along the arm turn about the axis across the arm and the vertical, the angle ramped over
// `ramp` either side of the elbow.
inline sdm::Mesh arm_bent(const sdm::Mesh& m, const sdm::Skeleton& s, double degrees, double at = 0.55) {
  const std::vector<Eigen::Vector3d> g = true_guess(s, m);
  const auto adj = s.adjacency();
  std::vector<int> ends;
  for (size_t k = 0; k < adj.size(); ++k)
    if (adj[k].size() == 1) ends.push_back(int(k));
  std::sort(ends.begin(), ends.end(), [&](int a, int b) { return g[a].y() < g[b].y(); });
  std::vector<int> best_chain;
  double best_len = -1;
  for (size_t e = 2; e < ends.size(); ++e) {
    std::vector<int> chain{ends[e]};
    int prev = -1, cur = ends[e];
    double len = 0;
    while (adj[cur].size() <= 2) {
      int next = -1;
      for (int j : adj[cur]) if (j != prev) next = j;
      if (next < 0) break;
      len += (g[next] - g[cur]).norm(), prev = cur, cur = next, chain.push_back(cur);
    }
    if (len > best_len) best_len = len, best_chain = chain;
  }
  std::reverse(best_chain.begin(), best_chain.end());  // junction -> hand
  double walked = 0;
  size_t el = 1;
  for (; el + 1 < best_chain.size(); ++el) {
    walked += (g[best_chain[el]] - g[best_chain[el - 1]]).norm();
    if (walked >= at * best_len) break;
  }
  const Eigen::Vector3d elbow = g[best_chain[el]];
  const Eigen::Vector3d dir = (g[best_chain.back()] - elbow).normalized();
  Eigen::Vector3d axis = dir.cross(Eigen::Vector3d::UnitY());
  if (axis.norm() < 0.3) axis = dir.cross(Eigen::Vector3d::UnitZ());
  axis.normalize();
  std::vector<bool> on_arm(adj.size(), false);
  for (size_t i = 1; i < best_chain.size(); ++i) on_arm[best_chain[i]] = true;
  const double ramp = 0.02 * sdm::bounding_box_diagonal(m);
  sdm::Mesh out = m;
  for (auto v : out.vertices()) {
    if (!on_arm[s.vertex_node[v.idx()]]) continue;
    const Eigen::Vector3d p = sdm::point(m, v);
    const double x = std::clamp(((p - elbow).dot(dir) + ramp) / (2 * ramp), 0.0, 1.0);
    const double a = degrees * M_PI / 180 * x * x * (3 - 2 * x);
    const Eigen::Vector3d q = elbow + Eigen::AngleAxisd(a, axis) * (p - elbow);
    out.set_point(v, sdm::Mesh::Point(q.x(), q.y(), q.z()));
  }
  return out;
}

}  // namespace faust
