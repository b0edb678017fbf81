#include "libstm/layout/segment_frames.h"

#include "libstm/core/errors.h"
#include "libstm/geometry/differential_geometry.h"

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

constexpr double kInf = std::numeric_limits<double>::infinity();

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

// Surface measures: vertex areas (a third of the incident faces), per node and per segment.
struct SurfaceAreas {
  std::vector<double> vertex, node, segment;
};

SurfaceAreas surface_areas(const Mesh& mesh, const Skeleton& sk, const std::vector<int>& face_segment) {
  const int ne = int(sk.edges.size());
  SurfaceAreas r{std::vector<double>(mesh.n_vertices(), 0.0), std::vector<double>(sk.nodes.size(), 0.0),
                 std::vector<double>(ne, 0.0)};
  for (auto f : mesh.faces()) {
    Eigen::Vector3d p[3];
    int k = 0;
    for (auto v : mesh.fv_range(f)) p[k++] = point(mesh, v);
    const double a = triangle_area(p[0], p[1], p[2]);
    for (auto v : mesh.fv_range(f)) r.vertex[v.idx()] += a / 3;
    const int s = face_segment[f.idx()];
    if (s >= 0 && s < ne) r.segment[s] += a;
  }
  for (size_t v = 0; v < mesh.n_vertices(); ++v) r.node[sk.vertex_node[v]] += r.vertex[v];
  return r;
}

// The skeleton as a graph weighted by edge length, its connected components and eccentricities.
struct SkeletonGraph {
  const Skeleton& sk;
  std::vector<std::vector<std::pair<int, int>>> adj;  // (neighbour, edge)
  std::vector<double> elen;
  std::vector<int> comp;  // component of each node
  int ncomp = 0;
  std::vector<double> ecc;  // graph distance to the farthest node of the component

  explicit SkeletonGraph(const Skeleton& skeleton);
  int nodes() const { return int(sk.nodes.size()); }
  // Dijkstra from every node with a finite dist (0 for the sources); parent_edge, when given,
  // receives the edge each improved node was reached by.
  void dijkstra(std::vector<double>& dist, std::vector<int>* parent_edge) const;

 private:
  void find_components();
  void find_eccentricities();
};

SkeletonGraph::SkeletonGraph(const Skeleton& skeleton) : sk(skeleton), adj(skeleton.nodes.size()), elen(skeleton.edges.size()) {
  for (int e = 0; e < int(sk.edges.size()); ++e) {
    const auto [a, b] = sk.edges[e];
    elen[e] = (sk.nodes[b] - sk.nodes[a]).norm();
    adj[a].push_back({b, e});
    if (b != a) adj[b].push_back({a, e});
  }
  find_components();
  find_eccentricities();
}

void SkeletonGraph::dijkstra(std::vector<double>& dist, std::vector<int>* parent_edge) const {
  const int nn = nodes();
  using QI = std::pair<double, int>;
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
}

void SkeletonGraph::find_components() {
  const int nn = nodes();
  comp.assign(nn, -1);
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
}

void SkeletonGraph::find_eccentricities() {
  const int nn = nodes();
  ecc.assign(nn, 0.0);
  for (int i = 0; i < nn; ++i) {
    if (adj[i].empty()) continue;
    std::vector<double> dist(nn, kInf);
    dist[i] = 0;
    dijkstra(dist, nullptr);
    for (int j = 0; j < nn; ++j)
      if (comp[j] == comp[i]) ecc[i] = std::max(ecc[i], dist[j]);
  }
}

// The root segment of component c, oriented from a to b (see the header); edge -1 for an
// isolated node. Eccentricities within 1e-9 of the component's diameter count as ties.
struct RootSegment {
  int edge = -1, a = -1, b = -1;
};

RootSegment root_segment(const SkeletonGraph& g, int c, const SurfaceAreas& area) {
  const Skeleton& sk = g.sk;
  RootSegment r;
  double best = kInf, diam = 0;
  for (int i = 0; i < g.nodes(); ++i)
    if (g.comp[i] == c) diam = std::max(diam, g.ecc[i]);
  const double tol = 1e-9 * std::max(diam, 1e-300);
  for (int e = 0; e < int(sk.edges.size()); ++e) {
    if (g.comp[sk.edges[e][0]] != c) continue;
    const double score = g.ecc[sk.edges[e][0]] + g.ecc[sk.edges[e][1]];
    if (r.edge < 0 || score < best - tol ||
        (std::abs(score - best) <= tol && area.segment[e] > area.segment[r.edge] * (1 + 1e-9))) {
      r.edge = e;
      best = score;
    }
  }
  if (r.edge < 0) return r;
  r.a = sk.edges[r.edge][0], r.b = sk.edges[r.edge][1];
  const double ea = g.ecc[r.a], eb = g.ecc[r.b];
  const bool swap = ea > eb + tol || (std::abs(ea - eb) <= tol && area.node[r.b] > area.node[r.a] * (1 + 1e-9));
  if (swap) std::swap(r.a, r.b);
  return r;
}

// Frames every segment of component c: the root's from the surface, the others carried along a
// Dijkstra tree from it (see the header).
void frame_component(const Mesh& mesh, const SkeletonGraph& g, int c, const SurfaceAreas& area, std::vector<SegmentFrame>& frames,
                     std::vector<char>& framed) {
  const Skeleton& sk = g.sk;
  const int nn = g.nodes(), ne = int(sk.edges.size());
  const RootSegment root = root_segment(g, c, area);
  if (root.edge < 0) return;  // an isolated node: no segment
  const int a0 = root.a, b0 = root.b;
  Eigen::Vector3d axis0 = sk.nodes[b0] - sk.nodes[a0];
  if (axis0.norm() > 0) axis0.normalize();
  else axis0 = Eigen::Vector3d::UnitZ();

  std::vector<Eigen::Vector3d> pts;
  std::vector<double> w;
  for (auto v : mesh.vertices())
    if (g.comp[sk.vertex_node[v.idx()]] == c) pts.push_back(point(mesh, v)), w.push_back(area.vertex[v.idx()]);
  const Eigen::Vector3d e1r = root_direction(pts, w, axis0);

  std::vector<Eigen::Vector3d> in_dir(nn, Eigen::Vector3d::Zero()), e1n(nn, Eigen::Vector3d::Zero());
  std::vector<char> out_side(nn, 0);
  std::vector<double> dist(nn, kInf);
  std::vector<int> parent(nn, -1);
  dist[a0] = dist[b0] = 0;
  parent[a0] = parent[b0] = root.edge;
  g.dijkstra(dist, &parent);
  frames[root.edge] = {a0, b0, axis0, e1r, axis0.cross(e1r)};
  framed[root.edge] = 1;
  in_dir[b0] = axis0, out_side[b0] = 1, e1n[b0] = e1r;
  in_dir[a0] = -axis0, out_side[a0] = 0, e1n[a0] = e1r;
  // Nodes in order of distance: a parent is always handled before its children.
  std::vector<int> order;
  for (int i = 0; i < nn; ++i)
    if (g.comp[i] == c) order.push_back(i);
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
    if (framed[e] || g.comp[sk.edges[e][0]] != c) continue;
    int p = sk.edges[e][0], q = sk.edges[e][1];
    if (dist[q] < dist[p] || (dist[q] == dist[p] && q < p)) std::swap(p, q);
    carry(p, q, e);
  }
}

}  // namespace

std::vector<SegmentFrame> segment_frames(const Mesh& mesh, const Skeleton& sk, const std::vector<int>& face_segment) {
  if (sk.vertex_node.size() != mesh.n_vertices())
    throw InputError("the skeleton maps " + std::to_string(sk.vertex_node.size()) + " vertices but the mesh has " +
                     std::to_string(mesh.n_vertices()));
  if (face_segment.size() != mesh.n_faces()) throw InputError("face_segment does not match the mesh");
  const SurfaceAreas area = surface_areas(mesh, sk, face_segment);
  const SkeletonGraph graph(sk);
  std::vector<SegmentFrame> frames(sk.edges.size());
  std::vector<char> framed(sk.edges.size(), 0);
  for (int c = 0; c < graph.ncomp; ++c) frame_component(mesh, graph, c, area, frames, framed);
  return frames;
}

}  // namespace sdm
