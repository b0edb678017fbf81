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

// The source's edges as a compressed adjacency: the neighbours of vertex v are
// to[offset[v]] .. to[offset[v + 1] - 1], at the edge lengths beside them.
struct EdgeGraph {
  std::vector<int> offset, to;
  std::vector<double> length;
};

EdgeGraph edge_graph(const Mesh& mesh) {
  EdgeGraph g;
  g.offset.reserve(mesh.n_vertices() + 1);
  g.offset.push_back(0);
  for (auto v : mesh.vertices()) {
    const Eigen::Vector3d p = point(mesh, v);
    for (auto h : mesh.voh_range(v)) {
      const auto w = mesh.to_vertex_handle(h);
      g.to.push_back(w.idx());
      g.length.push_back((point(mesh, w) - p).norm());
    }
    g.offset.push_back(int(g.to.size()));
  }
  return g;
}

// One thread's Dijkstra state: tentative distances (INFINITY where untouched, restored after each
// search), the vertices touched, and the heap of (distance, vertex).
struct Search {
  explicit Search(size_t vertices) : distance(vertices, INFINITY) {}
  std::vector<double> distance;
  std::vector<int> touched;
  std::vector<std::pair<double, int>> heap;
};

// The shortest path from vertex `from` along the edges to one of the face corners `corner`, plus
// the straight leg from that corner to the point (`leg`, per corner). Stops once the nearest
// unsettled vertex lies as far as the best path found: no corner beyond it can shorten that.
double path_to_point(const EdgeGraph& g, int from, const std::array<int, 3>& corner, const std::array<double, 3>& leg, Search& s) {
  for (int k = 0; k < 3; ++k)
    if (corner[k] == from) return leg[k];  // any other corner's path is longer by the triangle inequality
  const auto later = std::greater<std::pair<double, int>>();
  double best = INFINITY;
  s.distance[size_t(from)] = 0;
  s.touched.push_back(from);
  s.heap.assign(1, {0.0, from});
  while (!s.heap.empty()) {
    std::pop_heap(s.heap.begin(), s.heap.end(), later);
    const auto [d, u] = s.heap.back();
    s.heap.pop_back();
    if (d > s.distance[size_t(u)]) continue;  // a stale entry
    if (d >= best) break;
    for (int k = 0; k < 3; ++k)
      if (corner[k] == u) best = std::min(best, d + leg[k]);
    for (int e = g.offset[size_t(u)]; e < g.offset[size_t(u) + 1]; ++e) {
      const int v = g.to[size_t(e)];
      const double nd = d + g.length[size_t(e)];
      if (nd < s.distance[size_t(v)] && nd < best) {
        if (s.distance[size_t(v)] == INFINITY) s.touched.push_back(v);
        s.distance[size_t(v)] = nd;
        s.heap.emplace_back(nd, v);
        std::push_heap(s.heap.begin(), s.heap.end(), later);
      }
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
                                         int threads) {
  check_inputs(source, assigned, truth);
  const double area = surface_area(source), diagonal = bounding_box_diagonal(source);
  if (!(area > 0) || !(diagonal > 0)) throw InputError("correspondence error: the source mesh has no area");
  const EdgeGraph graph = edge_graph(source);
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
        Search search(source.n_vertices());
        for (size_t j = size_t(c) * kChunk; j < std::min(truth.size(), size_t(c + 1) * kChunk); ++j) {
          std::array<int, 3> corner{};
          std::array<double, 3> leg{};
          const Eigen::Vector3d p = position_of(source, assigned[j]);
          int k = 0;
          for (auto v : source.fv_range(source.face_handle(assigned[j].face))) {
            corner[size_t(k)] = v.idx();
            leg[size_t(k++)] = (point(source, v) - p).norm();
          }
          const Eigen::Vector3d true_point = point(source, source.vertex_handle(truth[j]));
          r.euclidean[j] = euclidean_unit * (p - true_point).norm();
          r.geodesic[j] = geodesic_unit * path_to_point(graph, truth[j], corner, leg, search);
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
