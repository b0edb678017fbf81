#include "libstm/transfer/transfer_texture.h"

#include "libstm/registration/carry_skeleton.h"
#include "libstm/skeleton/common_branching.h"
#include "libstm/core/errors.h"
#include "libstm/render/render_atlas.h"
#include "libstm/layout/segment_frames.h"
#include "libstm/layout/segments.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <sstream>

namespace sdm {

SkeletonOptions transfer_skeleton_options() {
  SkeletonOptions o;
  o.centre_junctions = 1e9;  // wherever in the cluster the widest ball is
  return o;
}
namespace {

// A chain of the shared graph as a polyline in one model, oriented like the source's chain.
struct Polyline {
  std::vector<Eigen::Vector3d> p;
  std::vector<double> s;  // arc length at every point
  double total() const { return s.back(); }

  explicit Polyline(std::vector<Eigen::Vector3d> pts) : p(std::move(pts)) {
    s.assign(p.size(), 0.0);
    for (size_t k = 1; k < p.size(); ++k) s[k] = s[k - 1] + (p[k] - p[k - 1]).norm();
  }
  Eigen::Vector3d at(double f) const {
    const double target = f * total();
    for (size_t k = 0; k + 1 < p.size(); ++k) {
      const double l = s[k + 1] - s[k];
      if (s[k + 1] >= target || k + 2 == p.size()) return l > 0 ? p[k] + (p[k + 1] - p[k]) * std::clamp((target - s[k]) / l, 0.0, 1.0) : p[k];
    }
    return p.front();
  }
  // Arc-length fraction of the point of the polyline nearest to q.
  double project(const Eigen::Vector3d& q) const {
    if (!(total() > 0)) return 0;
    double best = INFINITY, best_s = 0;
    for (size_t k = 0; k + 1 < p.size(); ++k) {
      double t = 0;
      const double d = distance_to_segment(q, p[k], p[k + 1], &t);
      if (d < best) best = d, best_s = s[k] + std::clamp(t, 0.0, 1.0) * (s[k + 1] - s[k]);
    }
    return best_s / total();
  }
};

// One model's side of the resampling: the reduced skeleton's chains expressed in the source's
// chain numbering and direction.
struct Side {
  const Mesh* mesh;
  const Skeleton* sk;
  std::vector<int> key_node;                 // shared key k -> this skeleton's node
  std::vector<int> chain;                    // source chain c -> this skeleton's chain
  std::vector<char> reversed;                // traversed against its stored direction
  std::vector<Polyline> lines;               // per source chain
  std::vector<int> edge_chain;               // this skeleton's edge -> source chain
  std::vector<Eigen::Vector3d> key_position;  // shared key k's position (a pure cycle's may move)
};

double chain_radius(const ReducedSkeleton::Chain& c, const std::vector<SegmentGeometry>& geo) {
  double sum = 0, len = 0;
  for (int e : c.edges) sum += geo[e].radius * std::max(geo[e].length, 1e-300), len += std::max(geo[e].length, 1e-300);
  return len > 0 ? sum / len : 0;
}

// Shared skeleton for one side: nodes placed on its polylines, vertices reassigned.
Skeleton resample(const Side& side, const ReducedSkeleton& red, const std::vector<int>& n, int nk,
                  const std::vector<std::vector<int>>& inner, const std::vector<std::array<int, 2>>& edges, int total_nodes,
                  const std::vector<int>& key_of_node) {
  const Skeleton& sk = *side.sk;
  const Mesh& mesh = *side.mesh;
  Skeleton out;
  out.nodes.resize(total_nodes);
  out.edges = edges;
  for (int k = 0; k < nk; ++k) out.nodes[k] = side.key_position[k];
  const int nc = int(n.size());
  for (int c = 0; c < nc; ++c)
    for (int j = 1; j < n[c]; ++j) out.nodes[inner[c][j - 1]] = side.lines[c].at(double(j) / n[c]);
  auto node_at = [&](int c, int j) {
    const auto& ch = red.chains[side.chain[c]];
    if (j <= 0) return key_of_node[side.reversed[c] ? ch.nodes.back() : ch.nodes.front()];
    if (j >= n[c]) return key_of_node[side.reversed[c] ? ch.nodes.front() : ch.nodes.back()];
    return inner[c][j - 1];
  };
  std::vector<std::vector<int>> node_edges(sk.nodes.size());
  for (size_t e = 0; e < sk.edges.size(); ++e) {
    node_edges[sk.edges[e][0]].push_back(int(e));
    if (sk.edges[e][1] != sk.edges[e][0]) node_edges[sk.edges[e][1]].push_back(int(e));
  }
  const int nv = int(mesh.n_vertices());
  out.vertex_node.assign(nv, -1);
  std::vector<int> v_chain(nv, -1);
  std::vector<double> v_arc(nv, 0);
  for (auto v : mesh.vertices()) {
    const int x = sk.vertex_node[v.idx()];
    const Eigen::Vector3d p = point(mesh, v);
    int best = -1;
    double best_d = INFINITY;
    for (int e : node_edges[x]) {
      const double d = distance_to_segment(p, sk.nodes[sk.edges[e][0]], sk.nodes[sk.edges[e][1]]);
      if (d < best_d * (1 - 1e-12)) best = e, best_d = d;
    }
    if (best < 0) {  // an isolated node: a key of its own
      out.vertex_node[v.idx()] = key_of_node[x];
      continue;
    }
    const int c = side.edge_chain[best];
    const double f = side.lines[c].project(p);
    v_chain[v.idx()] = c;
    v_arc[v.idx()] = f;
    out.vertex_node[v.idx()] = node_at(c, int(std::lround(f * n[c])));
  }
  // Nodes left without a vertex borrow the nearest one (in arc length along their chain, or in
  // space for a key) from a node that owns more than one.
  std::vector<int> count(total_nodes, 0);
  for (int x : out.vertex_node) ++count[x];
  auto borrow = [&](int node, auto distance) {
    int best = -1;
    double best_d = INFINITY;
    for (int v = 0; v < nv; ++v) {
      if (count[out.vertex_node[v]] < 2) continue;
      const double d = distance(v);
      if (d < best_d) best_d = d, best = v;
    }
    if (best < 0) return;
    --count[out.vertex_node[best]];
    out.vertex_node[best] = node;
    ++count[node];
  };
  for (int c = 0; c < nc; ++c)
    for (int j = 1; j < n[c]; ++j) {
      const int node = inner[c][j - 1];
      if (count[node] > 0) continue;
      const double f = double(j) / n[c];
      borrow(node, [&](int v) {
        return v_chain[v] == c ? std::abs(v_arc[v] - f) : 1e3 + (point(mesh, mesh.vertex_handle(v)) - out.nodes[node]).norm();
      });
    }
  for (int k = 0; k < nk; ++k)
    if (count[k] == 0) borrow(k, [&](int v) { return (point(mesh, mesh.vertex_handle(v)) - out.nodes[k]).norm(); });
  return out;
}

}  // namespace

SharedSkeletons share_skeletons(const Mesh& mesh_a, const Skeleton& given_a, const Mesh& mesh_b, const Skeleton& given_b,
                                const std::vector<std::pair<int, int>>& given_fixed, double split_ratio) {
  SharedSkeletons r;
  // Extracted skeletons of one shape can differ by a small branch (a tail found in one
  // tessellation only): both are pruned to their common branching first.
  const CommonBranching common = common_branching(given_a, given_b);
  const Skeleton& a = common.a;
  const Skeleton& b = common.b;
  r.pruned_a = common.pruned_a, r.pruned_b = common.pruned_b;
  r.node_a = common.a_original, r.node_b = common.b_original;
  std::vector<std::pair<int, int>> fixed;
  for (auto [x, y] : given_fixed) {
    const bool in_range = x >= 0 && y >= 0 && x < int(common.a_node.size()) && y < int(common.b_node.size());
    if (in_range && (common.a_node[x] < 0 || common.b_node[y] < 0))
      throw InputError("--match " + std::to_string(x) + "=" + std::to_string(y) + ": the node lies on a branch pruned to match the other skeleton");
    fixed.push_back(in_range ? std::make_pair(common.a_node[x], common.b_node[y]) : std::make_pair(x, y));
  }
  r.match = match_skeletons(a, b, fixed);
  const SkeletonMatch& m = r.match;
  const std::vector<SegmentGeometry> geo_a = segment_geometry(mesh_a, a, assign_faces(mesh_a, a));
  const std::vector<SegmentGeometry> geo_b = segment_geometry(mesh_b, b, assign_faces(mesh_b, b));
  const int nk = int(m.a.keys.size()), nc = int(m.a.chains.size());

  Side sa{&mesh_a, &a, {}, {}, {}, {}, {}, {}}, sb{&mesh_b, &b, {}, {}, {}, {}, {}, {}};
  for (int k = 0; k < nk; ++k) {
    sa.key_node.push_back(m.a.keys[k]);
    sb.key_node.push_back(m.b.keys[m.key_a_to_b[k]]);
    sa.key_position.push_back(a.nodes[sa.key_node[k]]);
    sb.key_position.push_back(b.nodes[sb.key_node[k]]);
  }
  // Centres and RMS sizes, to place a point of a on b. A pure cycle's start is arbitrary, and so is
  // the match's rotation about its axis (it aligns the rings' starts): rings are lined up by pose.
  auto centre_and_size = [](const Skeleton& s, Eigen::Vector3d& c) {
    c.setZero();
    for (const auto& p : s.nodes) c += p;
    c /= double(std::max<size_t>(1, s.nodes.size()));
    double r2 = 0;
    for (const auto& p : s.nodes) r2 += (p - c).squaredNorm();
    return std::sqrt(r2 / double(std::max<size_t>(1, s.nodes.size())));
  };
  Eigen::Vector3d ca0, cb0;
  const double size_a = centre_and_size(a, ca0), size_b = centre_and_size(b, cb0);
  sa.edge_chain.assign(a.edges.size(), -1);
  sb.edge_chain.assign(b.edges.size(), -1);
  std::vector<int> n(nc, 1);
  for (int c = 0; c < nc; ++c) {
    const auto& ca = m.a.chains[c];
    const auto [cbi, rev] = m.chain_a_to_b[c];
    const auto& cb = m.b.chains[cbi];
    sa.chain.push_back(c), sa.reversed.push_back(0);
    sb.chain.push_back(cbi), sb.reversed.push_back(rev ? 1 : 0);
    std::vector<Eigen::Vector3d> pa, pb;
    for (int x : ca.nodes) pa.push_back(a.nodes[x]);
    for (int x : cb.nodes) pb.push_back(b.nodes[x]);
    if (rev) std::reverse(pb.begin(), pb.end());
    if (ca.from == ca.to && m.a.key_degree[ca.from] == 2 && pb.size() > 2) {
      // A pure cycle: its key node is an arbitrary node of the ring (reduce_skeleton), so b's ring
      // starts over at the point nearest to where a's key lands, and the two rings line up.
      const Polyline ring(pb);
      const double f0 = ring.project(cb0 + (size_a > 0 ? size_b / size_a : 1.0) * (pa.front() - ca0));
      std::vector<Eigen::Vector3d> shifted{ring.at(f0)};
      for (size_t k = 1; k < pb.size(); ++k)
        if (ring.s[k] / ring.total() > f0) shifted.push_back(pb[k]);
      for (size_t k = 1; k < pb.size(); ++k)
        if (ring.s[k] / ring.total() <= f0) shifted.push_back(pb[k]);
      shifted.push_back(shifted.front());
      pb.clear();
      for (const auto& q : shifted)  // no zero-length pieces where the new start falls on a node
        if (pb.empty() || (q - pb.back()).norm() > 1e-12 * std::max(1.0, ring.total())) pb.push_back(q);
      if ((pb.back() - shifted.front()).norm() > 0) pb.push_back(shifted.front());
      sb.key_position[ca.from] = pb.front();
    }
    sa.lines.emplace_back(pa);
    sb.lines.emplace_back(pb);
    for (int e : ca.edges) sa.edge_chain[e] = c;
    for (int e : cb.edges) sb.edge_chain[e] = c;
    double want = double(std::max(ca.edges.size(), cb.edges.size()));
    if (split_ratio > 0 && std::isfinite(split_ratio)) {
      const double ra = chain_radius(ca, geo_a), rb = chain_radius(cb, geo_b);
      if (ra > 0) want = std::max(want, std::ceil(sa.lines.back().total() / (split_ratio * ra) - 1e-9));
      if (rb > 0) want = std::max(want, std::ceil(sb.lines.back().total() / (split_ratio * rb) - 1e-9));
    }
    if (ca.from == ca.to) want = std::max(want, 3.0);  // a loop needs three segments to stay a cycle of capsules
    n[c] = int(std::clamp(want, 1.0, 1000.0));
  }
  // The shared graph: keys first, then every chain's inner nodes; edges chain by chain.
  std::vector<std::vector<int>> inner(nc);
  std::vector<std::array<int, 2>> edges;
  int total_nodes = nk;
  r.chain_edges.resize(nc);
  for (int c = 0; c < nc; ++c) {
    const auto& ca = m.a.chains[c];
    std::vector<int> path{ca.from};
    for (int j = 1; j < n[c]; ++j) inner[c].push_back(total_nodes), path.push_back(total_nodes++);
    path.push_back(ca.to);
    for (size_t i = 0; i + 1 < path.size(); ++i) {
      r.chain_edges[c].push_back(int(edges.size()));
      edges.push_back({path[i], path[i + 1]});
    }
  }
  std::vector<int> key_a(a.nodes.size(), -1), key_b(b.nodes.size(), -1);
  for (int k = 0; k < nk; ++k) key_a[sa.key_node[k]] = k, key_b[sb.key_node[k]] = k;
  r.a = resample(sa, m.a, n, nk, inner, edges, total_nodes, key_a);
  r.b = resample(sb, m.b, n, nk, inner, edges, total_nodes, key_b);
  // The rotation between the shared skeletons (Kabsch over corresponding nodes): the match's,
  // except around pure cycles lined up above.
  Eigen::Vector3d sa0 = Eigen::Vector3d::Zero(), sb0 = Eigen::Vector3d::Zero();
  for (int i = 0; i < total_nodes; ++i) sa0 += r.a.nodes[i] / total_nodes, sb0 += r.b.nodes[i] / total_nodes;
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (int i = 0; i < total_nodes; ++i) H += (r.a.nodes[i] - sa0) * (r.b.nodes[i] - sb0).transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0) D(2, 2) = -1;
  r.rotation = svd.matrixV() * D * svd.matrixU().transpose();
  // Too few nodes to fix a rotation (a single straight chain): the match's.
  if (svd.singularValues()(1) <= 1e-9 * std::max(1e-300, svd.singularValues()(0))) r.rotation = m.rotation;
  return r;
}

Layout carry_layout(const Layout& la, const Mesh& mesh_b, const Skeleton& b, const Eigen::Matrix3d& rotation,
                    const std::vector<Eigen::Matrix3d>& segment_rotation) {
  if (b.nodes.size() != la.skeleton.nodes.size() || b.edges != la.skeleton.edges)
    throw InputError("the target skeleton's graph differs from the source layout's (resample it with share_skeletons first)");
  const std::vector<int> fs = assign_faces(mesh_b, b);
  const std::vector<SegmentGeometry> geo = segment_geometry(mesh_b, b, fs);
  Layout L = la;
  L.skeleton = b;
  for (size_t s = 0; s < L.segments.size(); ++s) {
    LayoutSegment& g = L.segments[s];
    const Eigen::Matrix3d& R = segment_rotation.size() == L.segments.size() ? segment_rotation[s] : rotation;
    const Eigen::Vector3d axis_a = R * g.axis;
    const Eigen::Vector3d d = b.nodes[g.b] - b.nodes[g.a];
    const Eigen::Vector3d axis = d.norm() > 0 ? Eigen::Vector3d(d.normalized()) : axis_a;
    g.e1 = transport_direction(R * g.e1, axis_a, axis);
    g.axis = axis;
    g.e2 = axis.cross(g.e1);
    g.radius = geo[s].radius, g.cap = geo[s].cap, g.length = geo[s].length, g.area = geo[s].area;
  }
  return L;
}

Skeleton skeleton_onto_graph(const Skeleton& graph, const Skeleton& target, const std::vector<std::pair<int, int>>& fixed,
                             SkeletonMatch* match) {
  const SkeletonMatch m = match_skeletons(graph, target, fixed);
  Skeleton out;
  out.nodes = graph.nodes;
  out.edges = graph.edges;
  for (size_t k = 0; k < m.a.keys.size(); ++k) out.nodes[m.a.keys[k]] = target.nodes[m.b.keys[m.key_a_to_b[k]]];
  for (size_t c = 0; c < m.a.chains.size(); ++c) {
    const auto& ca = m.a.chains[c];
    const auto& cb = m.b.chains[m.chain_a_to_b[c].first];
    std::vector<Eigen::Vector3d> pg, pt;
    for (int x : ca.nodes) pg.push_back(graph.nodes[x]);
    for (int x : cb.nodes) pt.push_back(target.nodes[x]);
    if (m.chain_a_to_b[c].second) std::reverse(pt.begin(), pt.end());
    const Polyline lg(pg), lt(pt);
    for (size_t j = 1; j + 1 < ca.nodes.size(); ++j)
      out.nodes[ca.nodes[j]] = lt.at(lg.total() > 0 ? lg.s[j] / lg.total() : double(j) / double(ca.nodes.size() - 1));
  }
  if (match) *match = m;
  return out;
}

TextureTransfer transfer_texture(GlContext& gl, const Mesh& source, const Image& texture, const Skeleton& skeleton_a,
                                 const Mesh& target, const Skeleton& skeleton_b, const TransferOptions& opt) {
  auto say = [&](const std::string& s) {
    if (opt.progress) opt.progress(s);
  };
  if (!source.has_halfedge_texcoords2D()) throw InputError("the source has no texture coordinates, so its texture cannot be transferred");
  TextureTransfer r;
  Skeleton sb = skeleton_b;
  std::vector<Eigen::Matrix3d> node_rotation;  // of skeleton_a's nodes, when bent onto the target
  std::vector<Eigen::Vector3d> placed;         // the source's vertices on the target (carried or bent)
  std::vector<std::pair<int, int>> fixed = opt.fixed;
  auto euler = [](const Mesh& m) { return long(m.n_vertices()) - long(m.n_edges()) + long(m.n_faces()); };
  if (opt.carry_same_shape && opt.fixed.empty() && euler(source) == euler(target)) {
    say("registering the source onto the target");
    // Besides the centred start, the similarity of the matched skeletons, when they match: it
    // finds a turned or moved target that the centred start cannot reach.
    std::vector<Similarity> starts;
    try {
      const SharedSkeletons sh = share_skeletons(source, skeleton_a, target, skeleton_b, {}, opt.split_ratio);
      starts.push_back(fit_similarity(sh.a.nodes, sh.b.nodes, std::vector<double>(sh.a.nodes.size(), 1.0)));
    } catch (const InputError&) {
    }
    r.registration = register_surfaces(source, target, starts);
    const Registration& g = r.registration;
    r.carried = g.rms <= opt.same_shape_rms && g.p99 <= opt.same_shape_p99;
    say("registered: RMS " + std::to_string(100 * g.rms) + " %, 99th percentile " + std::to_string(100 * g.p99) + " % of the diagonal, scale " +
        std::to_string(g.transform.scale) + (r.carried ? ": the same shape, the source's skeleton carried over" : ""));
    SkeletonFit best;
    if (!r.carried) {
      // Bent onto the target from the registration alone, and from the matched extracted skeleton
      // when the branchings match (it knows where a turned limb went); the closer fit is kept.
      say("bending the source's skeleton onto the target");
      std::vector<std::vector<Eigen::Vector3d>> guesses{{}};
      try {
        guesses.push_back(skeleton_onto_graph(skeleton_a, skeleton_b).nodes);
      } catch (const InputError&) {
      }
      for (const auto& guess : guesses) {
        SkeletonFit f = fit_skeleton(source, skeleton_a, target, g.transform, guess);
        if (f.rms < best.rms) best = std::move(f);
      }
      r.fit_rms = best.rms, r.fit_p99 = best.p99;
      // When bending explains little of the distance, the target is the source's shape and the
      // distance is the tessellations' (a coarse polyhedron and its remesh, which cuts its corners:
      // the double torus of the tests, 0.51 % moved as a whole, 0.40 % bent); moved as a whole,
      // the source lines up with it exactly, where the bent fit slides.
      r.carried = g.rms <= 2 * opt.same_shape_rms && g.p99 <= opt.same_shape_p99 && g.rms <= 1.5 * best.rms;
      r.fitted = !r.carried && best.rms <= opt.fit_rms && best.p99 <= opt.fit_p99 && best.end_spread >= opt.fit_spread;
      say("bent: RMS " + std::to_string(100 * best.rms) + " %, 99th percentile " + std::to_string(100 * best.p99) + " % of the diagonal" +
          (r.carried    ? ": little better than moved as a whole, so the same shape: the source's skeleton carried over"
           : r.fitted ? ": the source's skeleton bent onto the target"
                      : ": not close enough"));
    }
    if (r.carried) {
      sb = carry_skeleton(source, skeleton_a, target, g.transform);
      for (auto v : source.vertices()) placed.push_back(g.transform(point(source, v)));
    } else if (r.fitted) {
      sb = std::move(best.skeleton), node_rotation = std::move(best.node_rotation), placed = std::move(best.bent);
    }
    if (r.carried || r.fitted) {
      // One graph on both sides: every junction and end is its own counterpart.
      const std::vector<int> deg = skeleton_a.degrees();
      for (size_t x = 0; x < deg.size(); ++x)
        if (deg[x] != 2) fixed.emplace_back(int(x), int(x));
    }
  }
  say("matching the skeletons' branches");
  try {
    r.skeletons = share_skeletons(source, skeleton_a, target, sb, fixed, opt.split_ratio);
  } catch (const InputError& e) {
    if (!std::isfinite(r.registration.rms)) throw;
    auto pc = [](double x) {
      std::ostringstream o;
      o.precision(2);
      o << 100 * x << " %";
      return o.str();
    };
    throw InputError(std::string(e.what()) + "; nor is the target the source in another pose: moved as a whole, the source lies " +
                     pc(r.registration.rms) + " of the diagonal from it (RMS; the same shape is under " + pc(opt.same_shape_rms) +
                     "), bent along its skeleton " + pc(r.fit_rms) + " (under " + pc(opt.fit_rms) + " is taken)");
  }
  say("shared graph: " + std::to_string(r.skeletons.a.nodes.size()) + " nodes, " + std::to_string(r.skeletons.a.edges.size()) +
      " segments");
  LayoutOptions lo;
  lo.size = opt.size;
  lo.margin = opt.margin;
  lo.split_ratio = 0;  // the chains are resampled already: both models must keep the same graph
  lo.progress = opt.progress;
  r.layout_a = compute_layout(source, r.skeletons.a, lo);
  // A bent source's segments take the rotation of the fitted node nearest to them.
  std::vector<Eigen::Matrix3d> segment_rotation;
  if (r.fitted)
    for (const auto& e : r.skeletons.a.edges) {
      const Eigen::Vector3d mid = (r.skeletons.a.nodes[e[0]] + r.skeletons.a.nodes[e[1]]) / 2;
      size_t best = 0;
      for (size_t k = 1; k < skeleton_a.nodes.size(); ++k)
        if ((skeleton_a.nodes[k] - mid).norm() < (skeleton_a.nodes[best] - mid).norm()) best = k;
      segment_rotation.push_back(node_rotation[best]);
    }
  r.layout_b = carry_layout(r.layout_a, target, r.skeletons.b, r.skeletons.rotation, segment_rotation);
  say("remapping the source texture into its STM atlas");
  AtlasOptions ao;
  ao.progress = opt.progress;
  r.atlas = render_atlas(gl, source, r.layout_a, texture, ao);
  say("target STM coordinates");
  StmCoordinates sc;
  if (placed.empty()) {
    sc = stm_coordinates(target, r.layout_b);
  } else {
    // The source was carried or bent onto the target, so every target point has a source point
    // under it: the closest point of the placed source, taken back to the source by its barycentric
    // coordinates. Each target face is mapped by the source's capsules at those points, with the
    // segment of the source face under its centroid (one segment for the whole face, so seams and
    // borders between rectangles unwrap as in the source). The target then shows the source's texture
    // wherever the surfaces correspond, however far the fitted nodes are from where the target's
    // own shape would put them (capsule coordinates near a cap's pole turn fast: the fitted
    // skeleton's own capsules tore the spots at the back of a turned Spot's head).
    const std::vector<int> fa = assign_faces(source, r.skeletons.a);
    const Eigen::MatrixX3i F = face_matrix(source);
    // Source points under the target's vertices, then under its face centroids.
    std::vector<Eigen::Vector3d> points;
    for (auto v : target.vertices()) points.push_back(point(target, v));
    for (auto f : target.faces()) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (auto v : target.fv_range(f)) c += point(target, v) / 3;
      points.push_back(c);
    }
    const std::vector<SourcePoint> at = source_points_under(source, placed, points);
    Mesh under = target;
    for (auto v : target.vertices()) {
      const SourcePoint& q = at[v.idx()];
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) p += q.barycentric[k] * point(source, source.vertex_handle(F(q.face, k)));
      under.set_point(v, Mesh::Point(p.x(), p.y(), p.z()));
    }
    std::vector<int> face_segment;
    for (auto f : target.faces()) face_segment.push_back(fa[at[target.n_vertices() + f.idx()].face]);
    sc = stm_coordinates(under, r.layout_a, face_segment);
    for (auto v : target.vertices()) sc.mesh.set_point(v, target.point(v));
    sc.stretch = l2_stretch(sc.mesh);
  }
  r.target = std::move(sc.mesh);
  r.stretch = sc.stretch;
  r.seam_faces = sc.seam_faces;
  return r;
}

}  // namespace sdm
