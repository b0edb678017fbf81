#include "libstm/layout/segment_frames.h"

#include "libstm/core/errors.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace sdm {

Eigen::Vector3d transport_direction(const Eigen::Vector3d& e, const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  const double c = from.dot(to);
  Eigen::Vector3d r = e;
  if (c > -1 + 1e-12) {
    const Eigen::Vector3d v = from.cross(to);
    r = e * c + v.cross(e) + v * (v.dot(e) / (1 + c));  // Rodrigues with sin/cos from the cross/dot
  }
  r -= to * to.dot(r);
  const double n = r.norm();
  if (n > 1e-12) return r / n;
  // e was (anti)parallel to the new direction: any orthogonal direction is as good.
  Eigen::Vector3d any = std::abs(to.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return (any - to * to.dot(any)).normalized();
}

namespace {

Eigen::Vector3d any_orthogonal(const Eigen::Vector3d& t) {
  Eigen::Vector3d any = std::abs(t.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return (any - t * t.dot(any)).normalized();
}

// Reference direction of a part's surface in the plane orthogonal to `axis` (see header).
Eigen::Vector3d root_direction(const std::vector<Eigen::Vector3d>& pts, const std::vector<double>& w,
                               const Eigen::Vector3d& axis) {
  double W = 0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < pts.size(); ++i) W += w[i], c += w[i] * pts[i];
  if (!(W > 0)) return any_orthogonal(axis);
  c /= W;
  const Eigen::Vector3d p0 = any_orthogonal(axis), q0 = axis.cross(p0);
  Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
  Eigen::Vector2d m3 = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector2d> xs(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3d d = pts[i] - c;
    xs[i] = {d.dot(p0), d.dot(q0)};
    C += w[i] * xs[i] * xs[i].transpose();
    m3 += w[i] * xs[i].squaredNorm() * xs[i];
  }
  C /= W;
  m3 /= W;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(C);
  const double l0 = es.eigenvalues()(0), l1 = es.eigenvalues()(1);
  const double scale = std::max(l0 + l1, 1e-300);
  Eigen::Vector2d dir = es.eigenvectors().col(1);
  if (l1 - l0 < 1e-3 * scale) {
    // Round section: the principal axis is noise; the third moment still points at the bulge.
    if (m3.norm() > 1e-6 * std::pow(scale, 1.5)) dir = m3.normalized();
  } else {
    double t3 = 0;
    for (size_t i = 0; i < xs.size(); ++i) t3 += w[i] * std::pow(xs[i].dot(dir), 3);
    if (t3 < 0) dir = -dir;
  }
  return (dir.x() * p0 + dir.y() * q0).normalized();
}

}  // namespace

std::vector<SegmentFrame> segment_frames(const Mesh& mesh, const Skeleton& sk, const std::vector<int>& face_segment) {
  const int nn = int(sk.nodes.size()), ne = int(sk.edges.size());
  if (sk.vertex_node.size() != mesh.n_vertices())
    throw InputError("the skeleton maps " + std::to_string(sk.vertex_node.size()) + " vertices but the mesh has " +
                     std::to_string(mesh.n_vertices()));
  if (face_segment.size() != mesh.n_faces()) throw InputError("face_segment does not match the mesh");

  // Surface measures: vertex areas (a third of the incident faces), per node and per segment.
  std::vector<double> vertex_area(mesh.n_vertices(), 0.0), node_area(nn, 0.0), seg_area(ne, 0.0);
  for (auto f : mesh.faces()) {
    Eigen::Vector3d p[3];
    int k = 0;
    for (auto v : mesh.fv_range(f)) p[k++] = point(mesh, v);
    const double a = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    for (auto v : mesh.fv_range(f)) vertex_area[v.idx()] += a / 3;
    const int s = face_segment[f.idx()];
    if (s >= 0 && s < ne) seg_area[s] += a;
  }
  for (size_t v = 0; v < mesh.n_vertices(); ++v) node_area[sk.vertex_node[v]] += vertex_area[v];

  std::vector<std::vector<std::pair<int, int>>> adj(nn);  // (neighbour, edge)
  std::vector<double> elen(ne);
  for (int e = 0; e < ne; ++e) {
    const auto [a, b] = sk.edges[e];
    elen[e] = (sk.nodes[b] - sk.nodes[a]).norm();
    adj[a].push_back({b, e});
    if (b != a) adj[b].push_back({a, e});
  }
  using QI = std::pair<double, int>;
  auto dijkstra = [&](std::vector<double>& dist, std::vector<int>* parent_edge) {
    std::priority_queue<QI, std::vector<QI>, std::greater<QI>> q;
    for (int i = 0; i < nn; ++i)
      if (dist[i] == 0 || std::isfinite(dist[i])) q.push({dist[i], i});
    std::vector<char> done(nn, 0);
    while (!q.empty()) {
      const auto [d, u] = q.top();
      q.pop();
      if (done[u] || d > dist[u]) continue;
      done[u] = 1;
      for (const auto& [v, e] : adj[u]) {
        const double nd = d + elen[e];
        if (nd < dist[v]) {
          dist[v] = nd;
          if (parent_edge) (*parent_edge)[v] = e;
          q.push({nd, v});
        }
      }
    }
  };
  const double inf = std::numeric_limits<double>::infinity();

  // Components and eccentricities.
  std::vector<int> comp(nn, -1);
  int ncomp = 0;
  for (int i = 0; i < nn; ++i) {
    if (comp[i] >= 0) continue;
    std::vector<int> stack{i};
    comp[i] = ncomp;
    while (!stack.empty()) {
      const int u = stack.back();
      stack.pop_back();
      for (const auto& [v, e] : adj[u])
        if (comp[v] < 0) comp[v] = ncomp, stack.push_back(v);
    }
    ++ncomp;
  }
  std::vector<double> ecc(nn, 0.0);
  for (int i = 0; i < nn; ++i) {
    if (adj[i].empty()) continue;
    std::vector<double> dist(nn, inf);
    dist[i] = 0;
    dijkstra(dist, nullptr);
    for (int j = 0; j < nn; ++j)
      if (comp[j] == comp[i]) ecc[i] = std::max(ecc[i], dist[j]);
  }

  std::vector<SegmentFrame> frames(ne);
  std::vector<char> framed(ne, 0);
  for (int c = 0; c < ncomp; ++c) {
    // Root segment: the most central edge.
    int root = -1;
    double best = inf, diam = 0;
    for (int i = 0; i < nn; ++i)
      if (comp[i] == c) diam = std::max(diam, ecc[i]);
    const double tol = 1e-9 * std::max(diam, 1e-300);
    for (int e = 0; e < ne; ++e) {
      if (comp[sk.edges[e][0]] != c) continue;
      const double score = ecc[sk.edges[e][0]] + ecc[sk.edges[e][1]];
      if (root < 0 || score < best - tol || (std::abs(score - best) <= tol && seg_area[e] > seg_area[root] * (1 + 1e-9))) {
        root = e;
        best = score;
      }
    }
    if (root < 0) continue;  // an isolated node: no segment
    int a0 = sk.edges[root][0], b0 = sk.edges[root][1];
    {
      const double ea = ecc[a0], eb = ecc[b0];
      const bool swap = ea > eb + tol || (std::abs(ea - eb) <= tol && node_area[b0] > node_area[a0] * (1 + 1e-9));
      if (swap) std::swap(a0, b0);
    }
    Eigen::Vector3d axis0 = sk.nodes[b0] - sk.nodes[a0];
    if (axis0.norm() > 0) axis0.normalize();
    else axis0 = Eigen::Vector3d::UnitZ();

    std::vector<Eigen::Vector3d> pts;
    std::vector<double> w;
    for (auto v : mesh.vertices())
      if (comp[sk.vertex_node[v.idx()]] == c) pts.push_back(point(mesh, v)), w.push_back(vertex_area[v.idx()]);
    const Eigen::Vector3d e1r = root_direction(pts, w, axis0);

    std::vector<Eigen::Vector3d> in_dir(nn, Eigen::Vector3d::Zero()), e1n(nn, Eigen::Vector3d::Zero());
    std::vector<char> out_side(nn, 0);
    std::vector<double> dist(nn, inf);
    std::vector<int> parent(nn, -1);
    dist[a0] = dist[b0] = 0;
    parent[a0] = parent[b0] = root;
    dijkstra(dist, &parent);
    frames[root] = {a0, b0, axis0, e1r, axis0.cross(e1r)};
    framed[root] = 1;
    in_dir[b0] = axis0, out_side[b0] = 1, e1n[b0] = e1r;
    in_dir[a0] = -axis0, out_side[a0] = 0, e1n[a0] = e1r;
    // Nodes in order of distance: a parent is always handled before its children.
    std::vector<int> order;
    for (int i = 0; i < nn; ++i)
      if (comp[i] == c) order.push_back(i);
    std::sort(order.begin(), order.end(), [&](int i, int j) { return dist[i] != dist[j] ? dist[i] < dist[j] : i < j; });
    auto carry = [&](int p, int q, int e) {
      Eigen::Vector3d d = sk.nodes[q] - sk.nodes[p];
      d = d.norm() > 0 ? Eigen::Vector3d(d.normalized()) : in_dir[p];
      const Eigen::Vector3d e1 = transport_direction(e1n[p], in_dir[p], d);
      SegmentFrame f;
      if (out_side[p]) f.a = p, f.b = q, f.axis = d;
      else f.a = q, f.b = p, f.axis = -d;
      f.e1 = e1;
      f.e2 = f.axis.cross(e1);
      frames[e] = f;
      framed[e] = 1;
      return std::make_pair(d, e1);
    };
    for (int u : order) {
      if (u == a0 || u == b0) continue;
      const int e = parent[u];
      const int p = sk.edges[e][0] == u ? sk.edges[e][1] : sk.edges[e][0];
      const auto [d, e1] = carry(p, u, e);
      in_dir[u] = d, e1n[u] = e1, out_side[u] = out_side[p];
    }
    // Edges off the tree (cycles, parallel edges): carried from their end nearer the root.
    for (int e = 0; e < ne; ++e) {
      if (framed[e] || comp[sk.edges[e][0]] != c) continue;
      int p = sk.edges[e][0], q = sk.edges[e][1];
      if (dist[q] < dist[p] || (dist[q] == dist[p] && q < p)) std::swap(p, q);
      carry(p, q, e);
    }
  }
  return frames;
}

}  // namespace sdm
