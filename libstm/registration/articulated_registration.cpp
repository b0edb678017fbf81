#include "libstm/registration/articulated_registration.h"

#include "libstm/core/errors.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/geometry/vertex_normals.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/registration/closest_pairs.h"
#include "libstm/registration/skin_along_edges.h"
#include "libstm/registration/fit_skeleton.h"

#include <Eigen/Geometry>
#include <algorithm>

namespace sdm {

namespace {

using Skin = EdgeSkin;  // skin_along_edges.h

// The problem in the target's frame: the source and its nodes under the similarity of the nodes
// onto their guesses.
struct Problem {
  int N = 0, ns = 0, nt = 0;
  Eigen::MatrixX3i F;
  std::vector<Eigen::Vector3d> x, g, c, guess, tp, tn, tfn;  // source vertices, nodes, guesses; target vertices, normals, face normals
  std::vector<double> area_s, area_t;
  std::vector<std::vector<int>> adj;
  std::vector<Skin> skin;
  double diag = 1;
};

// Per node a rigid motion: x near node k goes to R_k (x - g_k) + g_k + t_k.
struct Motions {
  std::vector<Eigen::Matrix3d> R;
  std::vector<Eigen::Vector3d> t;
  Eigen::Vector3d apply(int k, const Eigen::Vector3d& y, const std::vector<Eigen::Vector3d>& g) const {
    return R[k] * (y - g[k]) + g[k] + t[k];
  }
};

// One closest pair: the source side as a blend of source vertices, the target point and the normal
// the point-to-plane term uses.
struct Pair {
  int vertex[3] = {0, 0, 0};
  double beta[3] = {1, 0, 0};
  int corners = 1;
  Eigen::Vector3d q, n;
  double weight = 0, distance = 0, area = 0;  // weight: area, or 0 for a pair left out
};

// Unit area-weighted vertex normals (vertex_normals.h); +z for a vertex without area.
std::vector<Eigen::Vector3d> vertex_normals_of(const Eigen::MatrixX3i& F, const std::vector<Eigen::Vector3d>& V) {
  std::vector<Eigen::Vector3d> n = vertex_area_vectors(F, V);
  for (auto& v : n) v = v.norm() > 0 ? Eigen::Vector3d(v.normalized()) : Eigen::Vector3d::UnitZ();
  return n;
}

Problem set_up(const Mesh& source, const Skeleton& skeleton, const Mesh& target, const std::vector<Eigen::Vector3d>& guess,
               Similarity& start) {
  Problem pr;
  pr.N = int(skeleton.nodes.size());
  pr.ns = int(source.n_vertices()), pr.nt = int(target.n_vertices());
  std::vector<double> owned(pr.N, 0.0);
  for (int n : skeleton.vertex_node) owned[n] += 1;
  start = fit_similarity(skeleton.nodes, guess, owned);
  pr.F = face_matrix(source);
  for (auto v : source.vertices()) pr.x.push_back(start(point(source, v)));
  for (const auto& p : skeleton.nodes) pr.g.push_back(start(p));
  pr.guess = guess;
  // Each node's anchor: the centroid of the vertices it owns, which a correct match puts at the guess.
  pr.c.assign(pr.N, Eigen::Vector3d::Zero());
  for (int v = 0; v < pr.ns; ++v) pr.c[skeleton.vertex_node[v]] += pr.x[v] / owned[skeleton.vertex_node[v]];
  for (int k = 0; k < pr.N; ++k)
    if (owned[k] == 0) pr.c[k] = pr.g[k];
  for (auto v : target.vertices()) pr.tp.push_back(point(target, v));
  const Eigen::MatrixX3i TF = face_matrix(target);
  pr.tn = vertex_normals_of(TF, pr.tp);
  for (int f = 0; f < TF.rows(); ++f)
    pr.tfn.push_back((pr.tp[TF(f, 1)] - pr.tp[TF(f, 0)]).cross(pr.tp[TF(f, 2)] - pr.tp[TF(f, 0)]).normalized());
  pr.area_s = vertex_areas(source, start.scale * start.scale), pr.area_t = vertex_areas(target, 1.0);
  pr.diag = std::max(bounding_box_diagonal(target), 1e-300);
  pr.adj = skeleton.adjacency();
  pr.skin = skin_along_edges(skeleton, pr.x, pr.g, pr.adj);
  return pr;
}

Eigen::Matrix3d minimal_rotation(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (!(a.norm() > 0) || !(b.norm() > 0)) return Eigen::Matrix3d::Identity();
  return Eigen::Quaterniond::FromTwoVectors(a, b).toRotationMatrix();
}

// First motions: t_k moves node k to its guess; R_k turns the node's edges onto the guesses' (the
// through-direction on a chain, the best rotation of the edges at a junction or an end).
Motions motions_from_guess(const Problem& pr) {
  Motions m{std::vector<Eigen::Matrix3d>(pr.N, Eigen::Matrix3d::Identity()), std::vector<Eigen::Vector3d>(pr.N)};
  const auto& g = pr.g;
  const auto& q = pr.guess;
  for (int k = 0; k < pr.N; ++k) {
    const std::vector<int>& adj = pr.adj[k];
    m.t[k] = q[k] - g[k];
    if (adj.size() == 1) {
      m.R[k] = minimal_rotation(g[adj[0]] - g[k], q[adj[0]] - q[k]);
    } else if (adj.size() == 2) {
      m.R[k] = minimal_rotation(g[adj[1]] - g[adj[0]], q[adj[1]] - q[adj[0]]);
    } else if (adj.size() > 2) {
      std::vector<Eigen::Vector3d> x{Eigen::Vector3d::Zero()}, y{Eigen::Vector3d::Zero()};
      for (int j : adj) x.push_back(g[j] - g[k]), y.push_back(q[j] - q[k]);
      m.R[k] = fit_similarity(x, y, std::vector<double>(x.size(), 1.0)).rotation;
    }
  }
  return m;
}

std::vector<Eigen::Vector3d> posed(const Problem& pr, const Motions& m) {
  std::vector<Eigen::Vector3d> out(pr.ns);
  for (int v = 0; v < pr.ns; ++v) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int i = 0; i < 2; ++i)
      if (pr.skin[v].w[i] > 0) p += pr.skin[v].w[i] * m.apply(pr.skin[v].node[i], pr.x[v], pr.g);
    out[v] = p;
  }
  return out;
}

// Closest pairs both ways between the posed source `vd` and the target (the target's normal with
// each): one per source vertex, one per target vertex (its closest point on the posed source as
// corners and barycentric weights). Pairs whose normals disagree by more than normal_angle or that lie
// further apart than `outlier` of the diagonal get weight 0 (they still count in the distances).
// `hints` (ns + nt faces, -1 at first) carry each query's face from one step to the next.
std::vector<Pair> make_pairs(const Problem& pr, const TriangleBvh& target_bvh, const std::vector<Eigen::Vector3d>& vd,
                             const ArticulatedOptions& opt, std::vector<int>& hints, int stride = 1) {
  const double min_cos = std::cos(opt.normal_angle * M_PI / 180), cut = opt.outlier * pr.diag;
  const std::vector<Eigen::Vector3d> sn = vertex_normals_of(pr.F, vd);
  return closest_pairs_both_ways<Pair>(
      target_bvh, vd, pr.F, pr.tp, hints, stride,
      [&](Pair& p, int v, const TriangleBvh::Closest& c) {
        p.vertex[0] = v, p.q = c.point, p.n = pr.tfn[c.face], p.weight = p.area = pr.area_s[v], p.distance = c.distance;
        if (sn[v].dot(p.n) < min_cos || c.distance > cut) p.weight = 0;
      },
      [&](Pair& p, int j, const TriangleBvh::Closest& c) {
        p.corners = 3;
        for (int k = 0; k < 3; ++k) p.vertex[k] = pr.F(c.face, k);
        const Eigen::Vector3d b = barycentric(c.point, vd[p.vertex[0]], vd[p.vertex[1]], vd[p.vertex[2]]);
        Eigen::Vector3d n = Eigen::Vector3d::Zero();
        for (int k = 0; k < 3; ++k) p.beta[k] = b[k], n += b[k] * sn[p.vertex[k]];
        p.q = pr.tp[j], p.n = pr.tn[j], p.weight = p.area = pr.area_t[j], p.distance = c.distance;
        if (n.normalized().dot(pr.tn[j]) < min_cos || c.distance > cut) p.weight = 0;
      });
}

Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& a) {
  Eigen::Matrix3d m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

// d/d(omega_k, dt_k) of motion k applied to y: a rotation R <- exp([omega]x) R and t <- t + dt.
Eigen::Matrix<double, 3, 6> motion_jacobian(const Problem& pr, const Motions& m, int k, const Eigen::Vector3d& y) {
  Eigen::Matrix<double, 3, 6> J;
  J << -cross_matrix(m.R[k] * (y - pr.g[k])), Eigen::Matrix3d::Identity();
  return J;
}

// Adds a * |r + sum_i J_i d_i|_P^2 (P a 3x3 metric) for the nodes `nodes` with Jacobians `J`.
void add_residual(const std::vector<int>& nodes, const std::vector<Eigen::Matrix<double, 3, 6>>& J, const Eigen::Vector3d& r,
                  const Eigen::Matrix3d& P, double a, Eigen::MatrixXd& M, Eigen::VectorXd& B) {
  for (size_t x = 0; x < nodes.size(); ++x) {
    const Eigen::Matrix<double, 6, 3> JtP = J[x].transpose() * P;
    B.segment<6>(6 * nodes[x]) -= a * JtP * r;
    for (size_t y = 0; y < nodes.size(); ++y) M.block<6, 6>(6 * nodes[x], 6 * nodes[y]) += a * JtP * J[y];
  }
}

// Data: sum over the pairs of weight/W * (alpha (n.(p - q))^2 + (1 - alpha) |p - q|^2).
void add_data(const Problem& pr, const Motions& m, const std::vector<Pair>& pairs, const std::vector<Eigen::Vector3d>& vd,
              double alpha, Eigen::MatrixXd& M, Eigen::VectorXd& B) {
  double W = 0;
  for (const Pair& p : pairs) W += p.weight;
  if (!(W > 0)) return;
  std::vector<int> nodes;
  std::vector<Eigen::Matrix<double, 3, 6>> J;
  for (const Pair& p : pairs) {
    if (p.weight <= 0) continue;
    nodes.clear(), J.clear();
    Eigen::Vector3d at = Eigen::Vector3d::Zero();
    for (int c = 0; c < p.corners; ++c) {
      const int v = p.vertex[c];
      at += p.beta[c] * vd[v];
      for (int i = 0; i < 2; ++i) {
        const double wk = p.beta[c] * pr.skin[v].w[i];
        if (wk == 0) continue;
        const int k = pr.skin[v].node[i];
        const Eigen::Matrix<double, 3, 6> Jk = wk * motion_jacobian(pr, m, k, pr.x[v]);
        const auto it = std::find(nodes.begin(), nodes.end(), k);
        if (it == nodes.end()) nodes.push_back(k), J.push_back(Jk);
        else J[it - nodes.begin()] += Jk;
      }
    }
    const Eigen::Matrix3d P = alpha * p.n * p.n.transpose() + (1 - alpha) * Eigen::Matrix3d::Identity();
    add_residual(nodes, J, at - p.q, P, p.weight / W, M, B);
  }
}

// Neighbours agree at their joint: motions k and j move the edge's ends and two points across its
// middle (a frame, so a twist between them counts too) alike; `weight` shared among the edges.
void add_joints(const Problem& pr, const Motions& m, double weight, Eigen::MatrixXd& M, Eigen::VectorXd& B) {
  int edges = 0;
  for (int k = 0; k < pr.N; ++k) edges += int(pr.adj[k].size());
  if (edges == 0) return;
  const double a = weight / (edges / 2) / 4;
  for (int k = 0; k < pr.N; ++k)
    for (int j : pr.adj[k]) {
      if (j < k) continue;
      const Eigen::Vector3d e = pr.g[j] - pr.g[k], mid = 0.5 * (pr.g[j] + pr.g[k]);
      Eigen::Vector3d u = e.unitOrthogonal() * e.norm();
      const Eigen::Vector3d ys[4] = {pr.g[k], pr.g[j], mid + u, mid + e.normalized().cross(u)};
      for (const Eigen::Vector3d& y : ys) {
        const std::vector<Eigen::Matrix<double, 3, 6>> J{motion_jacobian(pr, m, k, y), -motion_jacobian(pr, m, j, y)};
        add_residual({k, j}, J, m.apply(k, y, pr.g) - m.apply(j, y, pr.g), Eigen::Matrix3d::Identity(), a, M, B);
      }
    }
}

// Nodes towards their guesses: weight/N * |T_k(c_k) - guess_k|^2, c_k the centroid of node k's vertices.
void add_guesses(const Problem& pr, const Motions& m, double weight, Eigen::MatrixXd& M, Eigen::VectorXd& B) {
  const double a = weight / pr.N;
  for (int k = 0; k < pr.N; ++k) {
    const std::vector<Eigen::Matrix<double, 3, 6>> J{motion_jacobian(pr, m, k, pr.c[k])};
    add_residual({k}, J, m.apply(k, pr.c[k], pr.g) - pr.guess[k], Eigen::Matrix3d::Identity(), a, M, B);
  }
}

// One Gauss-Newton step of the articulated fit; returns the largest translation change.
double articulated_step(const Problem& pr, const TriangleBvh& target_bvh, const ArticulatedOptions& opt, double guess_weight,
                        Motions& m, std::vector<int>& hints) {
  const std::vector<Eigen::Vector3d> vd = posed(pr, m);
  const std::vector<Pair> pairs = make_pairs(pr, target_bvh, vd, opt, hints, std::max(opt.stride, 1));
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(6 * pr.N, 6 * pr.N);
  Eigen::VectorXd B = Eigen::VectorXd::Zero(6 * pr.N);
  add_data(pr, m, pairs, vd, std::clamp(opt.plane_weight, 0.0, 0.9), M, B);
  add_joints(pr, m, opt.joint_weight, M, B);
  add_guesses(pr, m, guess_weight, M, B);
  for (int k = 0; k < pr.N; ++k) {
    M.block<3, 3>(6 * k, 6 * k) += 1e-9 * pr.diag * pr.diag * Eigen::Matrix3d::Identity();
    M.block<3, 3>(6 * k + 3, 6 * k + 3) += 1e-9 * Eigen::Matrix3d::Identity();
  }
  const Eigen::VectorXd d = M.ldlt().solve(B);
  if (!d.allFinite()) return 0;
  double moved = 0;
  for (int k = 0; k < pr.N; ++k) {
    const Eigen::Vector3d w = d.segment<3>(6 * k), dt = d.segment<3>(6 * k + 3);
    if (w.norm() > 0) m.R[k] = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() * m.R[k];
    m.t[k] += dt;
    moved = std::max(moved, dt.norm());
  }
  return moved;
}

// Area-weighted RMS and 99th percentile of the pairs' distances, as fractions of the diagonal.
void distances(const Problem& pr, const std::vector<Pair>& pairs, double& rms, double& p99) {
  std::vector<double> d, w;
  double sum = 0, W = 0;
  for (size_t i = 0; i < pairs.size(); ++i) {
    const double wi = pairs[i].area;
    d.push_back(pairs[i].distance), w.push_back(wi), sum += wi * pairs[i].distance * pairs[i].distance, W += wi;
  }
  rms = W > 0 ? std::sqrt(sum / W) / pr.diag : INFINITY;
  p99 = weighted_quantile(d, w, 0.99) / pr.diag;
}

// The non-rigid refinement: fit_skeleton of the posed source (its nodes moved with it) onto the target.
std::vector<Eigen::Vector3d> refine(const Mesh& source, const Skeleton& posed_skeleton, const Mesh& target,
                                    const std::vector<Eigen::Vector3d>& vd) {
  Mesh m = source;
  for (auto v : m.vertices()) m.set_point(v, Mesh::Point(vd[v.idx()].x(), vd[v.idx()].y(), vd[v.idx()].z()));
  FitSkeletonOptions fo;
  fo.articulated_start = false;
  return fit_skeleton(m, posed_skeleton, target, Similarity(), {}, fo).bent;
}

}  // namespace

ArticulatedFit articulated_registration(const Mesh& source, const Skeleton& skeleton, const Mesh& target,
                                        const std::vector<Eigen::Vector3d>& node_guess, const ArticulatedOptions& opt) {
  if (skeleton.vertex_node.size() != source.n_vertices())
    throw InputError("the source skeleton maps " + std::to_string(skeleton.vertex_node.size()) + " vertices, the source has " +
                     std::to_string(source.n_vertices()));
  if (node_guess.size() != skeleton.nodes.size())
    throw InputError("articulated registration: " + std::to_string(node_guess.size()) + " node guesses for " +
                     std::to_string(skeleton.nodes.size()) + " skeleton nodes");
  if (source.n_faces() == 0 || target.n_faces() == 0) throw InputError("articulated registration: a mesh has no face");
  Similarity start;
  const Problem pr = set_up(source, skeleton, target, node_guess, start);
  const TriangleBvh target_bvh(vertex_matrix(target), face_matrix(target));
  Motions m = motions_from_guess(pr);
  ArticulatedFit fit;
  std::vector<int> hints;
  for (int it = 0; it < opt.iterations; ++it, ++fit.iterations) {
    const double gw = std::max(opt.guess_floor, opt.guess_weight * std::pow(0.5, double(it) / std::max(opt.guess_halving, 1)));
    if (articulated_step(pr, target_bvh, opt, gw, m, hints) < 1e-7 * pr.diag) break;
  }
  fit.posed = posed(pr, m);
  fit.skeleton.edges = skeleton.edges, fit.skeleton.vertex_node = skeleton.vertex_node;
  for (int k = 0; k < pr.N; ++k) {
    fit.skeleton.nodes.push_back(pr.g[k] + m.t[k]);
    Similarity s;
    s.scale = start.scale, s.rotation = m.R[k] * start.rotation;
    s.translation = m.R[k] * (start.translation - pr.g[k]) + pr.g[k] + m.t[k];
    fit.node_motion.push_back(s);
  }
  double unused = 0, turn = 0;
  for (const auto& e : skeleton.edges) {
    const Eigen::Matrix3d D = m.R[e[0]].transpose() * m.R[e[1]];
    turn += std::acos(std::clamp((D.trace() - 1) / 2, -1.0, 1.0)) * 180 / M_PI;
  }
  fit.twist = skeleton.edges.empty() ? 0 : turn / double(skeleton.edges.size());
  distances(pr, make_pairs(pr, target_bvh, fit.posed, opt, hints, std::max(opt.stride, 1)), fit.posed_rms, unused);
  fit.deformed = opt.refine ? refine(source, fit.skeleton, target, fit.posed) : fit.posed;
  distances(pr, make_pairs(pr, target_bvh, fit.deformed, opt, hints), fit.rms, fit.p99);
  if (opt.refine) {
    const SkeletonFit other = fit_skeleton(source, skeleton, target, start, node_guess);
    double rms = 0, p99 = 0;
    std::vector<int> other_hints;
    distances(pr, make_pairs(pr, target_bvh, other.bent, opt, other_hints), rms, p99);
    if (rms < fit.rms) fit.deformed = other.bent, fit.rms = rms, fit.p99 = p99, fit.refined_from_guesses = true;
  }
  return fit;
}

}  // namespace sdm
