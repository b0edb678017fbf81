#include "libstm/registration/fit_skeleton.h"

#include "libstm/registration/carry_skeleton.h"
#include "libstm/registration/closest_pairs.h"
#include "libstm/registration/skin_along_edges.h"
#include "libstm/core/errors.h"
#include "libstm/layout/segments.h"
#include "libstm/geometry/triangle_bvh.h"

#include <Eigen/Geometry>
#include <algorithm>

namespace sdm {

namespace {

using Skin = EdgeSkin;  // skin_along_edges.h

// The problem in the target's frame: the source and its skeleton where the start places them.
struct Frame {
  int N = 0, ns = 0, nt = 0;                // nodes, source vertices, target vertices
  Eigen::MatrixX3i F;                       // the source's faces
  std::vector<Eigen::Vector3d> v0, g, tp;   // source vertices and nodes (started), target vertices
  std::vector<double> area_s, area_t;       // vertex areas, both in target units
  double diag = 1;                          // the target's bounding-box diagonal
  std::vector<std::vector<int>> adj;        // the skeleton's neighbours
  std::vector<Skin> skin;                   // per source vertex
  // Per node, the mean squared distance of its vertices: the length that turns an error of its
  // linear map into a displacement; mean_size2 is their mean (and stands in for an empty node).
  std::vector<double> size2;
  double mean_size2 = 0;
};

// The embedded deformation's unknowns: a point x near node k goes to A_k (x - g_k) + g_k + t_k.
struct NodeMaps {
  std::vector<Eigen::Matrix3d> A;
  std::vector<Eigen::Vector3d> t;
};

// One closest-point pair: the bent-source side as a blend of source vertices (one vertex, or a
// face's corners), the target point, its weight and distance.
struct Pair {
  int vertex[3] = {0, 0, 0};
  double beta[3] = {1, 0, 0};
  int corners = 1;
  int face = -1;  // the bent source's face, for a target vertex's pair
  Eigen::Vector3d q;
  double weight = 0, distance = 0;
};

// Fills fr.size2 and fr.mean_size2 (area-weighted over each node's vertices; at least 1e-12 diag^2).
void node_sizes(const Skeleton& skeleton, Frame& fr) {
  std::vector<double> size2(fr.N, 0.0), own(fr.N, 0.0);
  for (int v = 0; v < fr.ns; ++v) {
    const int n = skeleton.vertex_node[v];
    size2[n] += fr.area_s[v] * (fr.v0[v] - fr.g[n]).squaredNorm(), own[n] += fr.area_s[v];
  }
  double mean_size2 = 0;
  for (int k = 0; k < fr.N; ++k) mean_size2 += own[k] > 0 ? size2[k] / own[k] : 0;
  mean_size2 = std::max(mean_size2 / std::max(fr.N, 1), 1e-12 * fr.diag * fr.diag);
  for (int k = 0; k < fr.N; ++k) size2[k] = own[k] > 0 && size2[k] > 0 ? size2[k] / own[k] : mean_size2;
  fr.size2 = std::move(size2);
  fr.mean_size2 = mean_size2;
}

// Everything in the target's frame: the source and its nodes as `start` places them.
Frame place_in_target(const Mesh& source, const Skeleton& skeleton, const Mesh& target, const Similarity& start) {
  Frame fr;
  fr.N = int(skeleton.nodes.size());
  fr.ns = int(source.n_vertices()), fr.nt = int(target.n_vertices());
  fr.F = face_matrix(source);
  fr.v0.resize(fr.ns), fr.g.resize(fr.N), fr.tp.resize(fr.nt);
  for (auto v : source.vertices()) fr.v0[v.idx()] = start(point(source, v));
  for (int k = 0; k < fr.N; ++k) fr.g[k] = start(skeleton.nodes[k]);
  for (auto v : target.vertices()) fr.tp[v.idx()] = point(target, v);
  fr.area_s = vertex_areas(source, start.scale * start.scale), fr.area_t = vertex_areas(target, 1.0);
  fr.diag = std::max(bounding_box_diagonal(target), 1e-300);
  fr.adj = skeleton.adjacency();
  fr.skin = skin_along_edges(skeleton, fr.v0, fr.g, fr.adj);
  node_sizes(skeleton, fr);
  return fr;
}

// The rotation taking direction a to direction b by the smallest angle.
Eigen::Matrix3d minimal_rotation(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (!(a.norm() > 0) || !(b.norm() > 0)) return Eigen::Matrix3d::Identity();
  return Eigen::Quaterniond::FromTwoVectors(a, b).toRotationMatrix();
}

// First maps from a guess of every node's place: t_k moves the node there; A_k turns the node's
// edges onto the guess's (through-direction on a chain, best rotation of the edges at a junction).
void maps_from_guess(const Frame& fr, const std::vector<Eigen::Vector3d>& guess, NodeMaps& maps) {
  const auto& g = fr.g;
  for (int k = 0; k < fr.N; ++k) {
    const std::vector<int>& adj = fr.adj[k];
    maps.t[k] = guess[k] - g[k];
    if (adj.size() == 1) {
      maps.A[k] = minimal_rotation(g[adj[0]] - g[k], guess[adj[0]] - guess[k]);
    } else if (adj.size() == 2) {
      maps.A[k] = minimal_rotation(g[adj[1]] - g[adj[0]], guess[adj[1]] - guess[adj[0]]);
    } else if (adj.size() > 2) {
      std::vector<Eigen::Vector3d> x{Eigen::Vector3d::Zero()}, y{Eigen::Vector3d::Zero()};
      for (int j : adj) x.push_back(g[j] - g[k]), y.push_back(guess[j] - guess[k]);
      maps.A[k] = fit_similarity(x, y, std::vector<double>(x.size(), 1.0)).rotation;
    }
  }
}

// The similarity that registers the source vertices `region` onto the target by closest points
// (at most 12 steps; after five, pairs beyond three median distances are left out), stopping when
// node k moves less than 1e-7 of the diagonal. A limb's region slides along and about its own axis
// for as long as it is let (FAUST 007 onto 024: none of 46 regions settled in 40 steps, still moving
// 1e-4 to 1e-3 of the diagonal a step); the fit after it pulls the regions together, and stopping at
// 12 instead of 40 left the bent fits of the tests within 2 % of their RMS (0.411 -> 0.404 %,
// 0.244 -> 0.245 %) at a third of the cost.
Similarity register_region(const Frame& fr, const TriangleBvh& target_bvh, const std::vector<int>& region, int k) {
  Similarity T;
  std::vector<Eigen::Vector3d> x, y;
  std::vector<double> w, d;
  std::vector<int> hints(region.size(), -1);  // each vertex's face at the previous step
  for (int it = 0; it < 12; ++it) {
    x.clear(), y.clear(), w.clear(), d.clear();
    for (size_t r = 0; r < region.size(); ++r) {
      const int v = region[r];
      const auto c = target_bvh.closest_point_near(T(fr.v0[v]), hints[r]);
      x.push_back(fr.v0[v]), y.push_back(c.point), w.push_back(fr.area_s[v]), d.push_back(c.distance);
    }
    if (it >= 5) {
      const double cut = 3 * weighted_quantile(d, w, 0.5);
      for (size_t i = 0; i < d.size(); ++i)
        if (d[i] > cut) w[i] = 0;
    }
    const Similarity N2 = fit_similarity(x, y, w);
    const double moved = (N2(fr.g[k]) - T(fr.g[k])).norm();
    T = N2;
    if (moved < 1e-7 * fr.diag) break;
  }
  return T;
}

// The articulated start: each node's neighbourhood (its vertices and its neighbours') registered on
// its own by a similarity, which becomes the node's first map; neighbourhoods of fewer than four
// vertices keep theirs. A limb turned at a joint starts turned, where the smooth fit alone slides
// the surface around it (Spot's head turned 30 degrees kept 0.05 of correspondence error).
void register_neighbourhoods(const Frame& fr, const Skeleton& skeleton, const TriangleBvh& target_bvh, NodeMaps& maps) {
  std::vector<std::vector<int>> owned(fr.N);
  for (int v = 0; v < fr.ns; ++v) owned[skeleton.vertex_node[v]].push_back(v);
  for (int k = 0; k < fr.N; ++k) {
    std::vector<int> region = owned[k];
    for (int j : fr.adj[k]) region.insert(region.end(), owned[j].begin(), owned[j].end());
    if (region.size() < 4) continue;
    const Similarity T = register_region(fr, target_bvh, region, k);
    maps.A[k] = T.scale * T.rotation;
    maps.t[k] = T(fr.g[k]) - fr.g[k];
  }
}

// The source's vertices under the node maps, each blended by its skin.
std::vector<Eigen::Vector3d> deformed(const Frame& fr, const NodeMaps& maps) {
  std::vector<Eigen::Vector3d> out(fr.ns);
  for (int v = 0; v < fr.ns; ++v) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int i = 0; i < 2; ++i) {
      const int k = fr.skin[v].node[i];
      if (fr.skin[v].w[i] == 0) continue;
      p += fr.skin[v].w[i] * (maps.A[k] * (fr.v0[v] - fr.g[k]) + fr.g[k] + maps.t[k]);
    }
    out[v] = p;
  }
  return out;
}

// Closest points both ways between the bent source `vd` and the target: first one pair per source
// vertex (weighted by its area), then one per target vertex (its closest point on the bent source
// as a face and barycentric coordinates). `hints` (ns + nt faces, -1 at first) carry each query's
// face from one step to the next.
std::vector<Pair> make_pairs(const Frame& fr, const TriangleBvh& target_bvh, const std::vector<Eigen::Vector3d>& vd,
                             std::vector<int>& hints, int stride = 1) {
  return closest_pairs_both_ways<Pair>(
      target_bvh, vd, fr.F, fr.tp, hints, stride,
      [&](Pair& p, int v, const TriangleBvh::Closest& c) {
        p.vertex[0] = v, p.q = c.point, p.weight = fr.area_s[v], p.distance = c.distance;
      },
      [&](Pair& p, int j, const TriangleBvh::Closest& c) {
        p.corners = 3;
        p.face = c.face;
        for (int k = 0; k < 3; ++k) p.vertex[k] = fr.F(c.face, k);
        const Eigen::Vector3d b = barycentric(c.point, vd[p.vertex[0]], vd[p.vertex[1]], vd[p.vertex[2]]);
        for (int k = 0; k < 3; ++k) p.beta[k] = b[k];
        p.q = fr.tp[j], p.weight = fr.area_t[j], p.distance = c.distance;
      });
}

// The normal equations M X = B of one step. Unknowns: per node k and coordinate r, row r of A_k
// and t_k[r]: X(4k + c, r).
struct NormalEquations {
  Eigen::MatrixXd M, B;
  explicit NormalEquations(int N) : M(Eigen::MatrixXd::Zero(4 * N, 4 * N)), B(Eigen::MatrixXd::Zero(4 * N, 3)) {}
};

// Data: sum over the pairs within `cut` of weight * |blend(x) - q|^2 / W.
void add_data_terms(const Frame& fr, const std::vector<Pair>& pairs, double cut, double W, NormalEquations& eq) {
  std::vector<int> nodes;
  std::vector<Eigen::Vector4d> coef;
  for (const Pair& p : pairs) {
    if (p.distance > cut) continue;
    nodes.clear(), coef.clear();
    Eigen::Vector3d fixed = Eigen::Vector3d::Zero();
    for (int c = 0; c < p.corners; ++c) {
      const int v = p.vertex[c];
      for (int i = 0; i < 2; ++i) {
        const double wk = p.beta[c] * fr.skin[v].w[i];
        if (wk == 0) continue;
        const int k = fr.skin[v].node[i];
        Eigen::Vector4d j;
        j << wk * (fr.v0[v] - fr.g[k]), wk;
        fixed += wk * fr.g[k];
        const auto at = std::find(nodes.begin(), nodes.end(), k);
        if (at == nodes.end()) nodes.push_back(k), coef.push_back(j);
        else coef[at - nodes.begin()] += j;
      }
    }
    const double a = p.weight / W;
    for (size_t x = 0; x < nodes.size(); ++x) {
      for (size_t y = 0; y < nodes.size(); ++y) eq.M.block<4, 4>(4 * nodes[x], 4 * nodes[y]) += a * coef[x] * coef[y].transpose();
      for (int r = 0; r < 3; ++r) eq.B.block<4, 1>(4 * nodes[x], r) += a * coef[x] * (p.q[r] - fixed[r]);
    }
  }
}

// Neighbours agree (Sumner's E_reg): A_k (g_j - g_k) + g_k + t_k = g_j + t_j per directed edge,
// `stiffness` shared among the directed edges.
void add_agreement_terms(const Frame& fr, double stiffness, NormalEquations& eq) {
  int directed = 0;
  for (int k = 0; k < fr.N; ++k) directed += int(fr.adj[k].size());
  const double lr = directed > 0 ? stiffness / directed : 0.0;
  for (int k = 0; k < fr.N; ++k)
    for (int j : fr.adj[k]) {
      const Eigen::Vector3d e = fr.g[j] - fr.g[k];
      Eigen::Vector4d ck, cj;
      ck << e, 1;
      cj << 0, 0, 0, -1;
      // Scaled by the node's size over the edge's, so long and short edges count alike.
      const double a = lr * fr.mean_size2 / std::max(e.squaredNorm(), 1e-12 * fr.diag * fr.diag);
      eq.M.block<4, 4>(4 * k, 4 * k) += a * ck * ck.transpose();
      eq.M.block<4, 4>(4 * j, 4 * j) += a * cj * cj.transpose();
      eq.M.block<4, 4>(4 * k, 4 * j) += a * ck * cj.transpose();
      eq.M.block<4, 4>(4 * j, 4 * k) += a * cj * ck.transpose();
      for (int r = 0; r < 3; ++r) {
        eq.B.block<4, 1>(4 * k, r) += a * ck * e[r];
        eq.B.block<4, 1>(4 * j, r) += a * cj * e[r];
      }
    }
}

// Near a rotation times a scale: rigidity * size2_k / N * |A_k - s_k R_k|^2, with R_k the rotation
// nearest to the current A_k and s_k its mean singular value clamped to [0.2, 5]; a tiny weight on
// every t_k keeps M regular.
void add_rigidity_terms(const Frame& fr, const NodeMaps& maps, double rigidity, NormalEquations& eq) {
  for (int k = 0; k < fr.N; ++k) {
    double trace = 0;
    const Eigen::Matrix3d R = nearest_rotation(maps.A[k], &trace);
    const double s = std::clamp(trace / 3, 0.2, 5.0);
    const double a = rigidity * fr.size2[k] / fr.N;
    eq.M.block<3, 3>(4 * k, 4 * k) += a * Eigen::Matrix3d::Identity();
    for (int r = 0; r < 3; ++r) eq.B.block<3, 1>(4 * k, r) += a * s * R.row(r).transpose();
    eq.M(4 * k + 3, 4 * k + 3) += 1e-12;
  }
}

// Solves the normal equations into `maps` (a node whose solution is not finite keeps its map);
// returns the largest change of a translation t_k.
double solve_maps(const Frame& fr, const NormalEquations& eq, NodeMaps& maps) {
  const Eigen::MatrixXd X = eq.M.ldlt().solve(eq.B);
  double moved = 0;
  for (int k = 0; k < fr.N; ++k) {
    Eigen::Matrix3d An;
    Eigen::Vector3d tn;
    for (int r = 0; r < 3; ++r) An.row(r) = X.block<3, 1>(4 * k, r).transpose(), tn[r] = X(4 * k + 3, r);
    if (!An.allFinite() || !tn.allFinite()) continue;
    moved = std::max(moved, (tn - maps.t[k]).norm());
    maps.A[k] = An, maps.t[k] = tn;
  }
  return moved;
}

// One non-rigid ICP step at `stiffness` (Amberg et al.): pairs of the current bend, then the node
// maps that minimise data + agreement + rigidity. False (maps unchanged) when no pair lies within
// the outlier distance; else `moved` is the largest change of a translation.
bool nonrigid_step(const Frame& fr, const TriangleBvh& target_bvh, const FitSkeletonOptions& opt, double stiffness,
                   NodeMaps& maps, std::vector<int>& hints, double& moved) {
  const std::vector<Pair> pairs = make_pairs(fr, target_bvh, deformed(fr, maps), hints, opt.stride);
  // Only gross outliers go: a limb still far from where it went must keep pulling (cutting at
  // three median distances left Spot's turned head behind: 1.0 % RMS against 0.27 %).
  const double cut = opt.outlier * fr.diag;
  double W = 0;
  for (const Pair& p : pairs)
    if (p.distance <= cut) W += p.weight;
  if (!(W > 0)) return false;
  NormalEquations eq(fr.N);
  add_data_terms(fr, pairs, cut, W, eq);
  add_agreement_terms(fr, stiffness, eq);
  add_rigidity_terms(fr, maps, opt.rigidity, eq);
  moved = solve_maps(fr, eq, maps);
  return true;
}

// The stiffness schedule: stiffness_start halved until a value at or below stiffness_end (within
// 0.01 %) is reached, that one included; iterations_per_stiffness steps each, fewer when a step
// moves no translation by 1e-7 of the diagonal or finds no pair. Returns the completed steps.
int fit_maps(const Frame& fr, const TriangleBvh& target_bvh, const FitSkeletonOptions& opt, NodeMaps& maps, std::vector<int>& hints) {
  int stages = 1;
  for (double s = opt.stiffness_start; s > opt.stiffness_end * 1.0001; s *= 0.5) ++stages;
  int iterations = 0;
  double stiffness = opt.stiffness_start;
  for (int stage = 0; stage < stages; ++stage, stiffness *= 0.5)
    for (int it = 0; it < opt.iterations_per_stiffness; ++it, ++iterations) {
      double moved = 0;
      if (!nonrigid_step(fr, target_bvh, opt, stiffness, maps, hints, moved) || moved < 1e-7 * fr.diag) break;
    }
  return iterations;
}

// rms and p99 of the final pairs (fractions of the diagonal); end_spread over pairs of end nodes
// moved by their t_k; area_ratio of the bent source over the target.
void measure_fit(const Frame& fr, const std::vector<Pair>& pairs, const std::vector<Eigen::Vector3d>& vd, const NodeMaps& maps,
                 SkeletonFit& result) {
  std::vector<double> d(pairs.size()), w(pairs.size());
  double sum = 0, W = 0;
  for (size_t i = 0; i < pairs.size(); ++i) {
    d[i] = pairs[i].distance, w[i] = pairs[i].weight;
    sum += w[i] * d[i] * d[i], W += w[i];
  }
  result.rms = W > 0 ? std::sqrt(sum / W) / fr.diag : INFINITY;
  result.p99 = weighted_quantile(d, w, 0.99) / fr.diag;
  const auto& g = fr.g;
  const auto& t = maps.t;
  for (int i = 0; i < fr.N; ++i)
    for (int j = i + 1; j < fr.N; ++j)
      if (fr.adj[i].size() == 1 && fr.adj[j].size() == 1 && (g[i] - g[j]).norm() > 0)
        result.end_spread = std::min(result.end_spread, (g[i] + t[i] - g[j] - t[j]).norm() / (g[i] - g[j]).norm());
  double bent_area = 0, target_area = 0;
  for (int f = 0; f < fr.F.rows(); ++f) bent_area += triangle_area(vd[fr.F(f, 0)], vd[fr.F(f, 1)], vd[fr.F(f, 2)]);
  for (double x : fr.area_t) target_area += x;
  result.area_ratio = target_area > 0 ? bent_area / target_area : 0;
}

// A node goes where the surface it carries went: the similarity that best moves its vertices
// (weighted by how much they follow it) onto their bent places, applied to the node. Its own
// translation t_k is not reliable: an end node's vertices all lie on one side of it (the cap), so
// a sheared A_k with another t_k moves them as well (a bent arm's end 0.33 off). A node that
// carries fewer than three vertices is moved by its own map, turned by its nearest rotation.
// Fills result.skeleton.nodes and result.node_rotation (the start's rotation included).
void place_nodes(const Frame& fr, const std::vector<Eigen::Vector3d>& vd, const NodeMaps& maps, const Similarity& start,
                 SkeletonFit& result) {
  std::vector<std::vector<Eigen::Vector3d>> px(fr.N), py(fr.N);
  std::vector<std::vector<double>> pw(fr.N);
  for (int v = 0; v < fr.ns; ++v)
    for (int i = 0; i < 2; ++i)
      if (fr.skin[v].w[i] > 0) {
        const int k = fr.skin[v].node[i];
        px[k].push_back(fr.v0[v]), py[k].push_back(vd[v]), pw[k].push_back(fr.skin[v].w[i] * fr.area_s[v]);
      }
  result.skeleton.nodes.resize(fr.N);
  result.node_rotation.resize(fr.N);
  for (int k = 0; k < fr.N; ++k) {
    Similarity local;
    if (px[k].size() >= 3) {
      local = fit_similarity(px[k], py[k], pw[k]);
    } else {
      local.rotation = nearest_rotation(maps.A[k]);
      local.translation = fr.g[k] + maps.t[k] - local.rotation * fr.g[k];
    }
    result.skeleton.nodes[k] = local(fr.g[k]);
    result.node_rotation[k] = local.rotation * start.rotation;
  }
}

// Target vertices take the node of the bent source's corner under them (the last nt pairs).
std::vector<int> target_vertex_nodes(const Mesh& source, const Skeleton& skeleton, const Mesh& target, const Frame& fr,
                                     const std::vector<Pair>& pairs, const std::vector<Eigen::Vector3d>& nodes) {
  std::vector<SourcePoint> under(fr.nt);
  for (int j = 0; j < fr.nt; ++j) {
    const Pair& p = pairs[fr.ns + j];
    under[j].face = p.face;
    under[j].barycentric = Eigen::Vector3d(p.beta[0], p.beta[1], p.beta[2]);
  }
  return vertex_nodes_through(source, skeleton, under, target, nodes);
}

}  // namespace

SkeletonFit fit_skeleton(const Mesh& source, const Skeleton& skeleton, const Mesh& target, const Similarity& start,
                         const std::vector<Eigen::Vector3d>& node_guess, const FitSkeletonOptions& opt) {
  if (skeleton.vertex_node.size() != source.n_vertices())
    throw InputError("the source skeleton maps " + std::to_string(skeleton.vertex_node.size()) + " vertices, the source has " +
                     std::to_string(source.n_vertices()));
  const Frame fr = place_in_target(source, skeleton, target, start);
  const TriangleBvh target_bvh(vertex_matrix(target), face_matrix(target));
  NodeMaps maps{std::vector<Eigen::Matrix3d>(fr.N, Eigen::Matrix3d::Identity()), std::vector<Eigen::Vector3d>(fr.N, Eigen::Vector3d::Zero())};
  if (int(node_guess.size()) == fr.N) {
    maps_from_guess(fr, node_guess, maps);
    if (int(opt.start_rotations.size()) == fr.N)
      for (int k = 0; k < fr.N; ++k) maps.A[k] = opt.start_rotations[size_t(k)] * start.rotation.transpose();
  }
  else if (opt.articulated_start) register_neighbourhoods(fr, skeleton, target_bvh, maps);

  SkeletonFit result;
  std::vector<int> hints;
  result.iterations = fit_maps(fr, target_bvh, opt, maps, hints);
  result.bent = deformed(fr, maps);
  const std::vector<Pair> pairs = make_pairs(fr, target_bvh, result.bent, hints);
  measure_fit(fr, pairs, result.bent, maps, result);
  result.skeleton.edges = skeleton.edges;
  place_nodes(fr, result.bent, maps, start, result);
  result.skeleton.vertex_node = target_vertex_nodes(source, skeleton, target, fr, pairs, result.skeleton.nodes);
  return result;
}

}  // namespace sdm
