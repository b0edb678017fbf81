#pragma once
// Where the FAUST correspondence error of register_bodies is (ground truth: vertex i <-> vertex i),
// for the hidden [faust_measure] case: per chain of the chosen match, as colours on the target,
// and per node as the angle between the registration's rotations and the true ones (each node's
// vertices and its neighbours' fitted by Kabsch onto their true places). DECISIONS 5, "Where the FAUST error is", quotes it.
#include "faust_pairs.h"

#include "libstm/core/image.h"
#include "libstm/geometry/differential_geometry.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/registration/fit_skeleton.h"
#include "libstm/correspondence/register_bodies.h"
#include "libstm/transfer/transfer_texture.h"

#include <Eigen/Geometry>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace diagnose {

// Per node of the shared source skeleton, its chain in the match (-1 for a junction).
inline std::vector<int> node_chains(const sdm::SharedSkeletons& sh) {
  std::vector<int> chain(sh.a.nodes.size(), -1);
  for (size_t c = 0; c < sh.chain_edges.size(); ++c)
    for (int e : sh.chain_edges[c])
      for (int x : sh.a.edges[e])
        if (chain[x] < 0) chain[x] = int(c);
  return chain;
}

// Per target vertex j, the distance (% of the source's diagonal) between the source point under it
// and source vertex j.
inline std::vector<double> vertex_errors(const sdm::Mesh& a, const sdm::Mesh& b, const sdm::BodyRegistration& r) {
  const auto under = sdm::source_points_under(a, r.placed, faust::points_of(b));
  const double diag = sdm::bounding_box_diagonal(a);
  std::vector<double> err(under.size());
  for (size_t j = 0; j < under.size(); ++j)
    err[j] = 100 * (faust::point_under(a, under[j]) - sdm::point(a, a.vertex_handle(int(j)))).norm() / diag;
  return err;
}

inline void print_chain_errors(const sdm::Mesh& a, const sdm::Mesh& b, const sdm::BodyRegistration& r) {
  const std::vector<int> chain = node_chains(r.skeletons);
  const std::vector<double> err = vertex_errors(a, b, r);
  const size_t n = r.skeletons.chain_edges.size() + 1;  // the last: junctions
  std::vector<double> sum(n, 0), count(n, 0);
  std::vector<Eigen::Vector3d> at(n, Eigen::Vector3d::Zero());
  for (size_t j = 0; j < err.size(); ++j) {
    const int c = chain[r.skeletons.a.vertex_node[j]] < 0 ? int(n) - 1 : chain[r.skeletons.a.vertex_node[j]];
    sum[c] += err[j], count[c] += 1, at[c] += sdm::point(a, a.vertex_handle(int(j)));
  }
  for (size_t c = 0; c < n; ++c)
    if (count[c] > 0)
      std::fprintf(stderr, "  chain %zu: %5.0f vertices, mean %.2f %%, centroid (%.2f %.2f %.2f)\n", c, count[c], sum[c] / count[c],
                   at[c].x() / count[c], at[c].y() / count[c], at[c].z() / count[c]);
}

// The target with uv along a colour ramp by its error (blue 0 %, green 2 %, red 4 % and more):
// PREFIXk.obj with PREFIXk.png, k counting the calls; `sdm render` draws it.
inline void write_error_colors(const sdm::Mesh& a, const sdm::Mesh& b, const sdm::BodyRegistration& r, const std::string& prefix) {
  const std::vector<double> err = vertex_errors(a, b, r);
  sdm::Mesh t = b;
  t.request_halfedge_texcoords2D();
  for (auto h : t.halfedges())
    if (!t.is_boundary(h))
      t.set_texcoord2D(h, sdm::Mesh::TexCoord2D(float(std::clamp(err[t.to_vertex_handle(h).idx()] / 6.0, 0.01, 0.99)), 0.5f));
  sdm::Image ramp(64, 4, 4, 255);
  for (int x = 0; x < 64; ++x)
    for (int y = 0; y < 4; ++y) {
      const double u = x / 63.0;
      ramp.pixels[4 * (y * 64 + x) + 0] = uint8_t(255 * std::clamp(3 * u - 1, 0.0, 1.0));
      ramp.pixels[4 * (y * 64 + x) + 1] = uint8_t(255 * std::clamp(1 - std::abs(3 * u - 1), 0.0, 1.0));
      ramp.pixels[4 * (y * 64 + x) + 2] = uint8_t(255 * std::clamp(1 - 3 * u, 0.0, 1.0));
    }
  static int count = 0;
  const std::string base = prefix + std::to_string(count++);
  sdm::write_png(ramp, base + ".png");
  sdm::write_mesh(t, base + ".obj", base + ".png");
}

inline double angle_between(const Eigen::Matrix3d& A, const Eigen::Matrix3d& B) {
  return std::acos(std::clamp(((A.transpose() * B).trace() - 1) / 2, -1.0, 1.0)) * 180 / M_PI;
}

// Per node of the shared source skeleton: the true rotation and the node's vertex count.
inline std::vector<Eigen::Matrix3d> true_rotations(const sdm::Mesh& a, const sdm::Mesh& b, const sdm::Skeleton& sk, std::vector<double>& weight) {
  const auto adj = sk.adjacency();
  std::vector<std::vector<int>> own(sk.nodes.size());
  for (size_t v = 0; v < sk.vertex_node.size(); ++v) own[sk.vertex_node[v]].push_back(int(v));
  std::vector<Eigen::Matrix3d> truth(sk.nodes.size(), Eigen::Matrix3d::Identity());
  weight.assign(sk.nodes.size(), 0);
  for (size_t k = 0; k < sk.nodes.size(); ++k) {
    std::vector<int> region = own[k];
    for (int j : adj[k]) region.insert(region.end(), own[j].begin(), own[j].end());
    std::vector<Eigen::Vector3d> x, y;
    for (int v : region) x.push_back(sdm::point(a, a.vertex_handle(v))), y.push_back(sdm::point(b, b.vertex_handle(v)));
    if (x.size() >= 3) truth[k] = sdm::fit_similarity(x, y, std::vector<double>(x.size(), 1.0)).rotation;
    weight[k] = double(own[k].size());
  }
  return truth;
}

// Each node's smallest rotation of its edges onto the matched target nodes' after the similarity
// `start` of the whole (fit_skeleton's start, as register_bodies calls it), start's rotation included.
inline std::vector<Eigen::Matrix3d> smallest_rotations(const sdm::SharedSkeletons& sh, const sdm::Similarity& start) {
  const auto adj = sh.a.adjacency();
  std::vector<Eigen::Vector3d> g;
  for (const auto& p : sh.a.nodes) g.push_back(start(p));
  const auto& q = sh.b.nodes;
  std::vector<Eigen::Matrix3d> R(g.size(), Eigen::Matrix3d::Identity());
  for (size_t k = 0; k < g.size(); ++k) {
    if (adj[k].size() == 1) {
      R[k] = Eigen::Quaterniond::FromTwoVectors(g[adj[k][0]] - g[k], q[adj[k][0]] - q[k]).toRotationMatrix();
    } else if (adj[k].size() == 2) {
      R[k] = Eigen::Quaterniond::FromTwoVectors(g[adj[k][1]] - g[adj[k][0]], q[adj[k][1]] - q[adj[k][0]]).toRotationMatrix();
    } else {
      std::vector<Eigen::Vector3d> x{Eigen::Vector3d::Zero()}, y{Eigen::Vector3d::Zero()};
      for (int j : adj[k]) x.push_back(g[j] - g[k]), y.push_back(q[j] - q[k]);
      R[k] = sdm::fit_similarity(x, y, std::vector<double>(x.size(), 1.0)).rotation;
    }
    R[k] = R[k] * start.rotation;
  }
  return R;
}

// Mean (by vertices) and per chain: the angle from the true rotation, and the part of it that
// turns the node's direction along its chain (the rest is twist about the chain).
inline void report_rotations(const char* what, const std::vector<Eigen::Matrix3d>& R, const std::vector<Eigen::Matrix3d>& truth,
                             const std::vector<double>& weight, const sdm::SharedSkeletons& sh) {
  const auto adj = sh.a.adjacency();
  const auto& g = sh.a.nodes;
  const std::vector<int> chain = node_chains(sh);
  const size_t n = sh.chain_edges.size() + 1;
  std::vector<double> total(n, 0), direction(n, 0), w(n, 0);
  double sum = 0, W = 0;
  for (size_t k = 0; k < R.size(); ++k) {
    const size_t c = chain[k] < 0 ? n - 1 : size_t(chain[k]);
    Eigen::Vector3d d = adj[k].size() == 2 ? Eigen::Vector3d(g[adj[k][1]] - g[adj[k][0]])
                        : adj[k].size() == 1 ? Eigen::Vector3d(g[adj[k][0]] - g[k]) : Eigen::Vector3d::UnitX();
    d.normalize();
    const double angle = angle_between(R[k], truth[k]);
    sum += weight[k] * angle, W += weight[k];
    total[c] += weight[k] * angle, w[c] += weight[k];
    direction[c] += weight[k] * std::acos(std::clamp((R[k] * d).dot(truth[k] * d), -1.0, 1.0)) * 180 / M_PI;
  }
  std::fprintf(stderr, "  rotations %s: mean %.1f degrees from the true ones (by vertices)\n", what, sum / std::max(W, 1.0));
  for (size_t c = 0; c < n; ++c)
    if (w[c] > 0) std::fprintf(stderr, "    chain %zu: %.0f degrees, of which direction %.0f\n", c, total[c] / w[c], direction[c] / w[c]);
}

inline void print_rotation_errors(const sdm::Mesh& a, const sdm::Mesh& b, const sdm::BodyRegistration& r) {
  std::vector<double> weight;
  const std::vector<Eigen::Matrix3d> truth = true_rotations(a, b, r.skeletons.a, weight);
  std::vector<double> owned(r.skeletons.a.nodes.size(), 0.0);
  for (int n : r.skeletons.a.vertex_node) owned[n] += 1;
  const sdm::Similarity start = sdm::fit_similarity(r.skeletons.a.nodes, r.skeletons.b.nodes, owned);
  report_rotations("at the start (smallest per node)", smallest_rotations(r.skeletons, start), truth, weight, r.skeletons);
  sdm::FitSkeletonOptions fo;
  fo.stride = 2;  // as register_bodies
  {
    sdm::FitSkeletonOptions f0 = fo;
    f0.iterations_per_stiffness = 0;
    report_rotations("at fit_skeleton's own start", sdm::fit_skeleton(a, r.skeletons.a, b, start, r.skeletons.b.nodes, f0).node_rotation, truth, weight, r.skeletons);
  }
  const auto fit = sdm::fit_skeleton(a, r.skeletons.a, b, start, r.skeletons.b.nodes, fo);
  report_rotations("after fit_skeleton", fit.node_rotation, truth, weight, r.skeletons);
  if (!std::getenv("SDM_MEASURE_ORACLE")) return;
  {  // The true node places (each node at the centroid of its vertices' true places), smallest rotations.
    const std::vector<Eigen::Vector3d> places = faust::true_guess(r.skeletons.a, b);
    const sdm::Similarity s2 = sdm::fit_similarity(r.skeletons.a.nodes, places, owned);
    const auto f2 = sdm::fit_skeleton(a, r.skeletons.a, b, s2, places, fo);
    const faust::Error e = faust::correspondence_error(a, sdm::source_points_under(a, f2.bent, faust::points_of(b)));
    std::fprintf(stderr, "  from the true node places: correspondence mean %.2f %%, p90 %.2f %%, beyond 5 %% %.1f %%\n", e.mean, e.p90, e.beyond5);
    report_rotations("  after that fit", f2.node_rotation, truth, weight, r.skeletons);
    sdm::FitSkeletonOptions fo3 = fo;
    fo3.start_rotations = truth;
    const auto f3 = sdm::fit_skeleton(a, r.skeletons.a, b, s2, places, fo3);
    const faust::Error e3 = faust::correspondence_error(a, sdm::source_points_under(a, f3.bent, faust::points_of(b)));
    std::fprintf(stderr, "  from the true node places and rotations: correspondence mean %.2f %%, p90 %.2f %%, beyond 5 %% %.1f %%\n", e3.mean, e3.p90, e3.beyond5);
  }
  // The same fit started from the true rotations: how much of the error the start explains.
  for (double stiffness_end : {0.01, 0.1, 0.5}) {
    sdm::FitSkeletonOptions fo2 = fo;
    fo2.start_rotations = truth, fo2.stiffness_end = stiffness_end;
    const auto f2 = sdm::fit_skeleton(a, r.skeletons.a, b, start, r.skeletons.b.nodes, fo2);
    const faust::Error e = faust::correspondence_error(a, sdm::source_points_under(a, f2.bent, faust::points_of(b)));
    std::fprintf(stderr, "  from the true rotations, stiffness down to %g: correspondence mean %.2f %%, p90 %.2f %%, beyond 5 %% %.1f %%, fit RMS %.3f %%\n",
                 stiffness_end, e.mean, e.p90, e.beyond5, 100 * f2.rms);
    report_rotations("  after that fit", f2.node_rotation, truth, weight, r.skeletons);
  }
}

}  // namespace diagnose
