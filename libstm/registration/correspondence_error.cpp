#include "libstm/registration/correspondence_error.h"

#include "libstm/core/errors.h"
#include "libstm/core/parallel.h"
#include "libstm/geometry/differential_geometry.h"
#include "libstm/mesh/mesh_geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numeric>
#include <string>
#include <utility>

namespace sdm {

namespace {

// The source's surface as a graph (Lanthier, Maheshwari and Sack 1997, "Approximating weighted
// shortest paths on polyhedral surfaces"): its vertices, then `steiner` points spread evenly on
// each edge (nodes n_vertices + steiner e + j - 1 at j / (steiner + 1) of edge e from its first
// halfedge's start), joined by straight segments across each face (any two of the face's boundary
// points not on one side of it) and along the edges (each point to the next). The neighbours of
// node u are to[offset[u]] .. to[offset[u + 1] - 1], at the lengths beside them. Every path of it
// lies on the surface, so its shortest paths bound the geodesics from above.
struct SurfaceGraph {
  int steiner = 0;
  std::vector<Eigen::Vector3d> position;  // per node
  std::vector<int> offset, to;
  std::vector<double> length;
};

// The boundary nodes of face f in their order around it (corner, the points of its first side,
// corner, ...): 3 (steiner + 1) of them, the corners at multiples of steiner + 1.
std::vector<int> face_boundary(const Mesh& mesh, int steiner, Mesh::FaceHandle f) {
  std::vector<int> nodes;
  nodes.reserve(size_t(3 * (steiner + 1)));
  for (auto h : mesh.fh_range(f)) {
    nodes.push_back(mesh.from_vertex_handle(h).idx());
    const int e = mesh.edge_handle(h).idx(), first = int(mesh.n_vertices()) + steiner * e;
    const bool forward = mesh.halfedge_handle(mesh.edge_handle(h), 0) == h;
    for (int j = 0; j < steiner; ++j) nodes.push_back(first + (forward ? j : steiner - 1 - j));
  }
  return nodes;
}

SurfaceGraph surface_graph(const Mesh& mesh, int steiner) {
  SurfaceGraph g;
  g.steiner = steiner;
  for (auto v : mesh.vertices()) g.position.push_back(point(mesh, v));
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    const Eigen::Vector3d a = point(mesh, mesh.from_vertex_handle(h)), b = point(mesh, mesh.to_vertex_handle(h));
    for (int j = 1; j <= steiner; ++j) g.position.push_back(a + (b - a) * (double(j) / (steiner + 1)));
  }
  // Across each face: boundary points on no common side (each such pair lies on one face only).
  // Along each edge: its corners and points in order (once per edge).
  const int ring = 3 * (steiner + 1), side = steiner + 1;
  auto across = [&](int i, int j) {  // positions around the face, i < j
    for (int s = 0; s < 3; ++s) {
      const auto on = [&](int k) { return (k >= s * side && k <= (s + 1) * side) || (s == 2 && k == 0); };
      if (on(i) && on(j)) return false;
    }
    return true;
  };
  std::vector<std::pair<int, int>> pairs;  // one of each joined pair
  pairs.reserve(mesh.n_faces() * size_t(ring * ring / 3) + mesh.n_edges() * size_t(steiner + 1));
  for (auto f : mesh.faces()) {
    const std::vector<int> nodes = face_boundary(mesh, steiner, f);
    for (int i = 0; i < ring; ++i)
      for (int j = i + 1; j < ring; ++j)
        if (across(i, j)) pairs.emplace_back(nodes[size_t(i)], nodes[size_t(j)]);
  }
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    int previous = mesh.from_vertex_handle(h).idx();
    for (int j = 0; j <= steiner; ++j) {
      const int next = j < steiner ? int(mesh.n_vertices()) + steiner * e.idx() + j : mesh.to_vertex_handle(h).idx();
      pairs.emplace_back(previous, next);
      previous = next;
    }
  }
  g.offset.assign(g.position.size() + 1, 0);
  for (const auto& [u, v] : pairs) ++g.offset[size_t(u) + 1], ++g.offset[size_t(v) + 1];
  std::partial_sum(g.offset.begin(), g.offset.end(), g.offset.begin());
  g.to.resize(size_t(g.offset.back()));
  g.length.resize(g.to.size());
  std::vector<int> fill(g.offset.begin(), g.offset.end() - 1);
  for (const auto& [u, v] : pairs) {
    const double l = (g.position[size_t(v)] - g.position[size_t(u)]).norm();
    g.to[size_t(fill[size_t(u)])] = v, g.length[size_t(fill[size_t(u)]++)] = l;
    g.to[size_t(fill[size_t(v)])] = u, g.length[size_t(fill[size_t(v)]++)] = l;
  }
  return g;
}

// One thread's Dijkstra state: tentative distances (INFINITY where untouched, restored after each
// search), the nodes touched, and the heap of (distance, node).
struct Search {
  explicit Search(size_t nodes) : distance(nodes, INFINITY) {}
  std::vector<double> distance;
  std::vector<int> touched;
  std::vector<std::pair<double, int>> heap;
};

// The shortest path from vertex `from` through the graph to one of the boundary nodes `exit` of
// the point's face, plus the straight leg across the face from that node to the point (`leg`, per
// exit). A* (Hart, Nilsson and Raphael 1968) ordered by the path so far plus the straight distance
// to the point `p`, which no path can beat (and which grows by at most an arc's length along an
// arc, so every node is settled once, at its shortest distance): the same length as Dijkstra's,
// over far fewer nodes. Stops once the best path found is no longer than any path through an
// unsettled node can be.
double path_to_point(const SurfaceGraph& g, int from, const Eigen::Vector3d& p, const std::vector<int>& exit, const std::vector<double>& leg,
                     Search& s) {
  for (size_t k = 0; k < exit.size(); ++k)
    if (exit[k] == from) return leg[k];  // the straight segment inside the face is the shortest path
  const auto later = std::greater<std::pair<double, int>>();
  const auto remaining = [&](int u) { return (g.position[size_t(u)] - p).norm(); };
  double best = INFINITY;
  s.distance[size_t(from)] = 0;
  s.touched.push_back(from);
  s.heap.assign(1, {remaining(from), from});
  while (!s.heap.empty()) {
    std::pop_heap(s.heap.begin(), s.heap.end(), later);
    const auto [f, u] = s.heap.back();
    s.heap.pop_back();
    if (f >= best) break;
    const double d = s.distance[size_t(u)];
    if (f > d + remaining(u)) continue;  // a stale entry
    for (size_t k = 0; k < exit.size(); ++k)
      if (exit[k] == u) best = std::min(best, d + leg[k]);
    for (int e = g.offset[size_t(u)]; e < g.offset[size_t(u) + 1]; ++e) {
      const int v = g.to[size_t(e)];
      const double nd = d + g.length[size_t(e)];
      if (nd >= s.distance[size_t(v)]) continue;
      const double nf = nd + remaining(v);
      if (nf >= best) continue;
      if (s.distance[size_t(v)] == INFINITY) s.touched.push_back(v);
      s.distance[size_t(v)] = nd;
      s.heap.emplace_back(nf, v);
      std::push_heap(s.heap.begin(), s.heap.end(), later);
    }
  }
  for (int v : s.touched) s.distance[size_t(v)] = INFINITY;
  s.touched.clear();
  return best;
}

// Throws InputError for counts or indices that do not fit the source.
void check_inputs(const Mesh& source, const std::vector<SourcePoint>& assigned, const std::vector<int>& truth) {
  if (assigned.size() != truth.size())
    throw InputError("correspondence error: " + std::to_string(assigned.size()) + " assigned source points for " +
                     std::to_string(truth.size()) + " true source vertices (one each per target vertex)");
  for (size_t j = 0; j < assigned.size(); ++j) {
    if (assigned[j].face < 0 || size_t(assigned[j].face) >= source.n_faces())
      throw InputError("correspondence error: target vertex " + std::to_string(j) + " is assigned face " +
                       std::to_string(assigned[j].face) + ", outside the source's " + std::to_string(source.n_faces()) + " faces");
    if (truth[j] < 0 || size_t(truth[j]) >= source.n_vertices())
      throw InputError("correspondence error: target vertex " + std::to_string(j) + " truly shows source vertex " +
                       std::to_string(truth[j]) + ", outside the source's " + std::to_string(source.n_vertices()) + " vertices");
  }
}

}  // namespace

CorrespondenceError correspondence_error(const Mesh& source, const std::vector<SourcePoint>& assigned, const std::vector<int>& truth,
                                         int threads, int steiner) {
  check_inputs(source, assigned, truth);
  const double area = surface_area(source), diagonal = bounding_box_diagonal(source);
  if (!(area > 0) || !(diagonal > 0)) throw InputError("correspondence error: the source mesh has no area");
  if (steiner < 0) throw InputError("correspondence error: a negative number of points per edge");
  const SurfaceGraph graph = surface_graph(source, steiner);
  const double geodesic_unit = 100 / std::sqrt(area), euclidean_unit = 100 / diagonal;
  CorrespondenceError r;
  r.geodesic.assign(truth.size(), 0.0);
  r.euclidean.assign(truth.size(), 0.0);
  // Chunks of target vertices, each with its own search state (the results do not depend on which
  // thread takes a chunk).
  constexpr int kChunk = 256;
  const int chunks = int((truth.size() + kChunk - 1) / kChunk);
  parallel_for(
      chunks, 1,
      [&](int c) {
        Search search(graph.position.size());
        std::vector<double> leg;
        for (size_t j = size_t(c) * kChunk; j < std::min(truth.size(), size_t(c + 1) * kChunk); ++j) {
          const Eigen::Vector3d p = position_of(source, assigned[j]);
          const std::vector<int> exit = face_boundary(source, steiner, source.face_handle(assigned[j].face));
          leg.resize(exit.size());
          for (size_t k = 0; k < exit.size(); ++k) leg[k] = (graph.position[size_t(exit[k])] - p).norm();
          const Eigen::Vector3d true_point = point(source, source.vertex_handle(truth[j]));
          r.euclidean[j] = euclidean_unit * (p - true_point).norm();
          r.geodesic[j] = geodesic_unit * path_to_point(graph, truth[j], p, exit, leg, search);
        }
      },
      threads);
  if (truth.empty()) return r;
  const double n = double(truth.size());
  const std::vector<double> unit(truth.size(), 1.0);
  r.geodesic_mean = std::accumulate(r.geodesic.begin(), r.geodesic.end(), 0.0) / n;
  r.euclidean_mean = std::accumulate(r.euclidean.begin(), r.euclidean.end(), 0.0) / n;
  r.geodesic_p90 = weighted_quantile(r.geodesic, unit, 0.9);
  r.euclidean_p90 = weighted_quantile(r.euclidean, unit, 0.9);
  return r;
}

}  // namespace sdm
