#include "libstm/registration/fit_skeleton.h"

#include "libstm/registration/carry_skeleton.h"
#include "libstm/core/errors.h"
#include "libstm/layout/segments.h"
#include "libstm/geometry/triangle_bvh.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>

namespace sdm {

namespace {

// A surface point's blend of node maps: the two ends of the skeleton edge it lies along.
struct Skin {
  int node[2] = {0, 0};
  double w[2] = {1, 0};
};

// Rotation and scale nearest to A (polar decomposition; reflections excluded).
void nearest_rotation(const Eigen::Matrix3d& A, Eigen::Matrix3d& R, double& s) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d d(1, 1, 1);
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) d(2) = -1;
  R = svd.matrixU() * d.asDiagonal() * svd.matrixV().transpose();
  s = std::clamp(svd.singularValues().cwiseProduct(d).sum() / 3, 0.2, 5.0);
}

// The rotation taking direction a to direction b by the smallest angle.
Eigen::Matrix3d minimal_rotation(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (!(a.norm() > 0) || !(b.norm() > 0)) return Eigen::Matrix3d::Identity();
  return Eigen::Quaterniond::FromTwoVectors(a, b).toRotationMatrix();
}

}  // namespace

SkeletonFit fit_skeleton(const Mesh& source, const Skeleton& skeleton, const Mesh& target, const Similarity& start,
                         const std::vector<Eigen::Vector3d>& node_guess, const FitSkeletonOptions& opt) {
  if (skeleton.vertex_node.size() != source.n_vertices())
    throw InputError("the source skeleton maps " + std::to_string(skeleton.vertex_node.size()) + " vertices, the source has " +
                     std::to_string(source.n_vertices()));
  const int N = int(skeleton.nodes.size());
  const int ns = int(source.n_vertices()), nt = int(target.n_vertices());
  const Eigen::MatrixX3i F = face_matrix(source);
  // Everything in the target's frame: the source as the start places it.
  std::vector<Eigen::Vector3d> v0(ns), g(N), tp(nt);
  for (auto v : source.vertices()) v0[v.idx()] = start(point(source, v));
  for (int k = 0; k < N; ++k) g[k] = start(skeleton.nodes[k]);
  for (auto v : target.vertices()) tp[v.idx()] = point(target, v);
  const std::vector<double> area_s = vertex_areas(source, start.scale * start.scale), area_t = vertex_areas(target, 1.0);
  const double diag = std::max(bounding_box_diagonal(target), 1e-300);
  const std::vector<std::vector<int>> adj = skeleton.adjacency();

  std::vector<Skin> skin(ns);
  for (int v = 0; v < ns; ++v) {
    const int n = skeleton.vertex_node[v];
    Skin& s = skin[v];
    s.node[0] = s.node[1] = n;
    double best = INFINITY;
    for (int m : adj[n]) {
      double t = 0;
      const double d = distance_to_segment(v0[v], g[n], g[m], &t);
      if (d < best) {
        best = d;
        t = std::clamp(t, 0.0, 1.0);
        s.node[1] = m, s.w[0] = 1 - t, s.w[1] = t;
      }
    }
  }
  // Per node, the mean squared distance of its vertices: the length that turns an error of its
  // linear map into a displacement.
  std::vector<double> size2(N, 0.0), own(N, 0.0);
  for (int v = 0; v < ns; ++v) {
    const int n = skeleton.vertex_node[v];
    size2[n] += area_s[v] * (v0[v] - g[n]).squaredNorm(), own[n] += area_s[v];
  }
  double mean_size2 = 0;
  for (int k = 0; k < N; ++k) mean_size2 += own[k] > 0 ? size2[k] / own[k] : 0;
  mean_size2 = std::max(mean_size2 / std::max(N, 1), 1e-12 * diag * diag);
  for (int k = 0; k < N; ++k) size2[k] = own[k] > 0 && size2[k] > 0 ? size2[k] / own[k] : mean_size2;

  // Unknowns: per node k and coordinate r, row r of A_k and t_k[r]: X(4k + c, r).
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(4 * N, 3);
  std::vector<Eigen::Matrix3d> A(N, Eigen::Matrix3d::Identity());
  std::vector<Eigen::Vector3d> t(N, Eigen::Vector3d::Zero());
  if (int(node_guess.size()) == N) {
    for (int k = 0; k < N; ++k) {
      t[k] = node_guess[k] - g[k];
      // The first map turns the node's edges onto the guess's: through-direction on a chain,
      // best rotation of the edges at a junction.
      if (adj[k].size() == 1) {
        A[k] = minimal_rotation(g[adj[k][0]] - g[k], node_guess[adj[k][0]] - node_guess[k]);
      } else if (adj[k].size() == 2) {
        A[k] = minimal_rotation(g[adj[k][1]] - g[adj[k][0]], node_guess[adj[k][1]] - node_guess[adj[k][0]]);
      } else if (adj[k].size() > 2) {
        std::vector<Eigen::Vector3d> x{Eigen::Vector3d::Zero()}, y{Eigen::Vector3d::Zero()};
        for (int j : adj[k]) x.push_back(g[j] - g[k]), y.push_back(node_guess[j] - node_guess[k]);
        A[k] = fit_similarity(x, y, std::vector<double>(x.size(), 1.0)).rotation;
      }
    }
  }
  const TriangleBvh target_bvh(vertex_matrix(target), face_matrix(target));
  if (int(node_guess.size()) != N && opt.articulated_start) {
    // Each node's neighbourhood (its vertices and its neighbours') registered on its own by a
    // similarity: a limb turned at a joint starts turned, where the smooth fit alone slides the
    // surface around it (Spot's head turned 30 degrees kept 0.05 of correspondence error).
    std::vector<std::vector<int>> owned(N);
    for (int v = 0; v < ns; ++v) owned[skeleton.vertex_node[v]].push_back(v);
    for (int k = 0; k < N; ++k) {
      std::vector<int> region = owned[k];
      for (int j : adj[k]) region.insert(region.end(), owned[j].begin(), owned[j].end());
      if (region.size() < 4) continue;
      Similarity T;
      std::vector<Eigen::Vector3d> x, y;
      std::vector<double> w, d;
      for (int it = 0; it < 40; ++it) {
        x.clear(), y.clear(), w.clear(), d.clear();
        for (int v : region) {
          const auto c = target_bvh.closest_point(T(v0[v]));
          x.push_back(v0[v]), y.push_back(c.point), w.push_back(area_s[v]), d.push_back(c.distance);
        }
        if (it >= 5) {
          const double cut = 3 * weighted_quantile(d, w, 0.5);
          for (size_t i = 0; i < d.size(); ++i)
            if (d[i] > cut) w[i] = 0;
        }
        const Similarity N2 = fit_similarity(x, y, w);
        const double moved = (N2(g[k]) - T(g[k])).norm();
        T = N2;
        if (moved < 1e-7 * diag) break;
      }
      A[k] = T.scale * T.rotation;
      t[k] = T(g[k]) - g[k];
    }
  }
  for (int k = 0; k < N; ++k)
    for (int r = 0; r < 3; ++r) {
      X.block<3, 1>(4 * k, r) = A[k].row(r).transpose();
      X(4 * k + 3, r) = t[k][r];
    }

  auto deformed = [&](std::vector<Eigen::Vector3d>& out) {
    out.resize(ns);
    for (int v = 0; v < ns; ++v) {
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      for (int i = 0; i < 2; ++i) {
        const int k = skin[v].node[i];
        if (skin[v].w[i] == 0) continue;
        p += skin[v].w[i] * (A[k] * (v0[v] - g[k]) + g[k] + t[k]);
      }
      out[v] = p;
    }
  };
  auto source_bvh = [&](const std::vector<Eigen::Vector3d>& vd) {
    Eigen::MatrixX3d V(ns, 3);
    for (int v = 0; v < ns; ++v) V.row(v) = vd[v].transpose();
    return TriangleBvh(V, F);
  };

  // One pair: the bent-source side as a blend of source vertices (one vertex, or a face's corners),
  // the target point, its weight and distance.
  struct Pair {
    int vertex[3] = {0, 0, 0};
    double beta[3] = {1, 0, 0};
    int corners = 1;
    int face = -1;  // the bent source's face, for a target vertex's pair
    Eigen::Vector3d q;
    double weight = 0, distance = 0;
  };
  auto make_pairs = [&](const std::vector<Eigen::Vector3d>& vd, std::vector<Pair>& pairs) {
    pairs.clear();
    const TriangleBvh bvh = source_bvh(vd);
    for (int v = 0; v < ns; ++v) {
      const auto c = target_bvh.closest_point(vd[v]);
      Pair p;
      p.vertex[0] = v, p.q = c.point, p.weight = area_s[v], p.distance = c.distance;
      pairs.push_back(p);
    }
    for (int j = 0; j < nt; ++j) {
      const auto c = bvh.closest_point(tp[j]);
      Pair p;
      p.corners = 3;
      p.face = c.face;
      for (int i = 0; i < 3; ++i) p.vertex[i] = F(c.face, i);
      const Eigen::Vector3d b = barycentric(c.point, vd[p.vertex[0]], vd[p.vertex[1]], vd[p.vertex[2]]);
      for (int i = 0; i < 3; ++i) p.beta[i] = b[i];
      p.q = tp[j], p.weight = area_t[j], p.distance = c.distance;
      pairs.push_back(p);
    }
  };

  SkeletonFit result;
  std::vector<Eigen::Vector3d> vd;
  std::vector<Pair> pairs;
  int stages = 1;
  for (double s = opt.stiffness_start; s > opt.stiffness_end * 1.0001; s *= 0.5) ++stages;
  double stiffness = opt.stiffness_start;
  for (int stage = 0; stage < stages; ++stage, stiffness *= 0.5) {
    for (int it = 0; it < opt.iterations_per_stiffness; ++it, ++result.iterations) {
      deformed(vd);
      make_pairs(vd, pairs);
      // Only gross outliers go: a limb still far from where it went must keep pulling (cutting at
      // three median distances left Spot's turned head behind: 1.0 % RMS against 0.27 %).
      const double cut = opt.outlier * diag;
      double W = 0;
      for (const Pair& p : pairs)
        if (p.distance <= cut) W += p.weight;
      if (!(W > 0)) break;

      Eigen::MatrixXd M = Eigen::MatrixXd::Zero(4 * N, 4 * N);
      Eigen::MatrixXd B = Eigen::MatrixXd::Zero(4 * N, 3);
      // Data: sum over pairs of weight * |blend(x) - q|^2 / W.
      std::vector<int> nodes;
      std::vector<Eigen::Vector4d> coef;
      for (const Pair& p : pairs) {
        if (p.distance > cut) continue;
        nodes.clear(), coef.clear();
        Eigen::Vector3d fixed = Eigen::Vector3d::Zero();
        for (int c = 0; c < p.corners; ++c) {
          const int v = p.vertex[c];
          for (int i = 0; i < 2; ++i) {
            const double wk = p.beta[c] * skin[v].w[i];
            if (wk == 0) continue;
            const int k = skin[v].node[i];
            Eigen::Vector4d j;
            j << wk * (v0[v] - g[k]), wk;
            fixed += wk * g[k];
            const auto at = std::find(nodes.begin(), nodes.end(), k);
            if (at == nodes.end()) nodes.push_back(k), coef.push_back(j);
            else coef[at - nodes.begin()] += j;
          }
        }
        const double a = p.weight / W;
        for (size_t x = 0; x < nodes.size(); ++x) {
          for (size_t y = 0; y < nodes.size(); ++y) M.block<4, 4>(4 * nodes[x], 4 * nodes[y]) += a * coef[x] * coef[y].transpose();
          for (int r = 0; r < 3; ++r) B.block<4, 1>(4 * nodes[x], r) += a * coef[x] * (p.q[r] - fixed[r]);
        }
      }
      // Neighbours agree: A_k (g_j - g_k) + g_k + t_k = g_j + t_j, per directed edge.
      int directed = 0;
      for (int k = 0; k < N; ++k) directed += int(adj[k].size());
      const double lr = directed > 0 ? stiffness / directed : 0.0;
      for (int k = 0; k < N; ++k)
        for (int j : adj[k]) {
          const Eigen::Vector3d e = g[j] - g[k];
          Eigen::Vector4d ck, cj;
          ck << e, 1;
          cj << 0, 0, 0, -1;
          // Scaled by the node's size over the edge's, so long and short edges count alike.
          const double a = lr * mean_size2 / std::max(e.squaredNorm(), 1e-12 * diag * diag);
          M.block<4, 4>(4 * k, 4 * k) += a * ck * ck.transpose();
          M.block<4, 4>(4 * j, 4 * j) += a * cj * cj.transpose();
          M.block<4, 4>(4 * k, 4 * j) += a * ck * cj.transpose();
          M.block<4, 4>(4 * j, 4 * k) += a * cj * ck.transpose();
          for (int r = 0; r < 3; ++r) {
            B.block<4, 1>(4 * k, r) += a * ck * e[r];
            B.block<4, 1>(4 * j, r) += a * cj * e[r];
          }
        }
      // Near a rotation times a scale: |A_k - s_k R_k|^2 with R_k, s_k from the current A_k.
      for (int k = 0; k < N; ++k) {
        Eigen::Matrix3d R;
        double s = 1;
        nearest_rotation(A[k], R, s);
        const double a = opt.rigidity * size2[k] / N;
        M.block<3, 3>(4 * k, 4 * k) += a * Eigen::Matrix3d::Identity();
        for (int r = 0; r < 3; ++r) B.block<3, 1>(4 * k, r) += a * s * R.row(r).transpose();
        M(4 * k + 3, 4 * k + 3) += 1e-12;
      }
      X = M.ldlt().solve(B);
      double moved = 0;
      for (int k = 0; k < N; ++k) {
        Eigen::Matrix3d An;
        Eigen::Vector3d tn;
        for (int r = 0; r < 3; ++r) An.row(r) = X.block<3, 1>(4 * k, r).transpose(), tn[r] = X(4 * k + 3, r);
        if (!An.allFinite() || !tn.allFinite()) continue;
        moved = std::max(moved, (tn - t[k]).norm());
        A[k] = An, t[k] = tn;
      }
      if (moved < 1e-7 * diag) break;
    }
  }

  deformed(vd);
  make_pairs(vd, pairs);
  std::vector<double> d(pairs.size()), w(pairs.size());
  double sum = 0, W = 0;
  for (size_t i = 0; i < pairs.size(); ++i) {
    d[i] = pairs[i].distance, w[i] = pairs[i].weight;
    sum += w[i] * d[i] * d[i], W += w[i];
  }
  result.rms = W > 0 ? std::sqrt(sum / W) / diag : INFINITY;
  result.p99 = weighted_quantile(d, w, 0.99) / diag;

  result.bent = vd;
  for (int i = 0; i < N; ++i)
    for (int j = i + 1; j < N; ++j)
      if (adj[i].size() == 1 && adj[j].size() == 1 && (g[i] - g[j]).norm() > 0)
        result.end_spread = std::min(result.end_spread, (g[i] + t[i] - g[j] - t[j]).norm() / (g[i] - g[j]).norm());
  double bent_area = 0, target_area = 0;
  for (int f = 0; f < F.rows(); ++f) bent_area += 0.5 * (vd[F(f, 1)] - vd[F(f, 0)]).cross(vd[F(f, 2)] - vd[F(f, 0)]).norm();
  for (double x : area_t) target_area += x;
  result.area_ratio = target_area > 0 ? bent_area / target_area : 0;
  Skeleton& out = result.skeleton;
  out.edges = skeleton.edges;
  out.nodes.resize(N);
  result.node_rotation.resize(N);
  // A node goes where the surface it carries went: the similarity that best moves its vertices
  // (weighted by how much they follow it) onto their bent places, applied to the node. Its own
  // translation t_k is not reliable: an end node's vertices all lie on one side of it (the cap), so
  // a sheared A_k with another t_k moves them as well (a bent arm's end 0.33 off).
  std::vector<std::vector<Eigen::Vector3d>> px(N), py(N);
  std::vector<std::vector<double>> pw(N);
  for (int v = 0; v < ns; ++v)
    for (int i = 0; i < 2; ++i)
      if (skin[v].w[i] > 0) {
        const int k = skin[v].node[i];
        px[k].push_back(v0[v]), py[k].push_back(vd[v]), pw[k].push_back(skin[v].w[i] * area_s[v]);
      }
  for (int k = 0; k < N; ++k) {
    Similarity local;
    if (px[k].size() >= 3) {
      local = fit_similarity(px[k], py[k], pw[k]);
    } else {
      double s = 1;
      nearest_rotation(A[k], local.rotation, s);
      local.translation = g[k] + t[k] - local.rotation * g[k];
    }
    out.nodes[k] = local(g[k]);
    result.node_rotation[k] = local.rotation * start.rotation;
  }
  // Target vertices take the node of the bent source's corner under them (the last pairs).
  std::vector<SourcePoint> under(nt);
  for (int j = 0; j < nt; ++j) {
    const Pair& p = pairs[ns + j];
    under[j].face = p.face;
    under[j].barycentric = Eigen::Vector3d(p.beta[0], p.beta[1], p.beta[2]);
  }
  out.vertex_node = vertex_nodes_through(source, skeleton, under, target, out.nodes);
  return result;
}

}  // namespace sdm
