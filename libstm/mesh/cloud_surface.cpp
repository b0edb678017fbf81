#include "libstm/mesh/cloud_surface.h"

#include "libstm/core/errors.h"
#include "libstm/core/parallel.h"
#include "libstm/core/stopwatch.h"
#include "libstm/geometry/point_kdtree.h"
#include "libstm/mesh/drop_small_parts.h"
#include "libstm/mesh/fill_holes.h"
#include "libstm/mesh/load_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace sdm {
namespace {

// A grid over the cloud's bounding box with a border of two cells; corners are numbered
// i + nx (j + ny k).
struct Grid {
  Eigen::Vector3d origin;
  double cell = 0;
  int64_t n[3] = {0, 0, 0};
  int64_t key(int64_t i, int64_t j, int64_t k) const { return i + n[0] * (j + n[1] * k); }
  Eigen::Vector3d position(int64_t key) const {
    const int64_t i = key % n[0], j = (key / n[0]) % n[1], k = key / (n[0] * n[1]);
    return origin + cell * Eigen::Vector3d(double(i), double(j), double(k));
  }
};

Grid make_grid(const std::vector<Eigen::Vector3d>& points, double cell) {
  Eigen::Vector3d lo = points[0], hi = points[0];
  for (const auto& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  Grid g;
  g.cell = cell;
  g.origin = lo - Eigen::Vector3d::Constant(2 * cell);
  for (int a = 0; a < 3; ++a) g.n[a] = int64_t(std::ceil((hi[a] - lo[a]) / cell)) + 5;
  return g;
}

// The cells holding a point and the cells around them (the zero set lies within noise of the
// points, so within one cell of a cell with points), sorted, each once.
std::vector<int64_t> active_cells(const std::vector<Eigen::Vector3d>& points, const Grid& g) {
  std::vector<int64_t> own;
  own.reserve(points.size());
  for (const auto& p : points) {
    const Eigen::Vector3d c = (p - g.origin) / g.cell;
    own.push_back(g.key(int64_t(c.x()), int64_t(c.y()), int64_t(c.z())));
  }
  std::sort(own.begin(), own.end());
  own.erase(std::unique(own.begin(), own.end()), own.end());
  std::vector<int64_t> cells;
  cells.reserve(own.size() * 27);
  for (int64_t c : own)
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) cells.push_back(c + g.key(di, dj, dk));
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  return cells;
}

// Corner offsets of a cube by bits (x = 1, y = 2, z = 4), and the six tetrahedra around the
// diagonal 0-7: 0, one axis, two axes, 7 for each order of the axes.
constexpr int kTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

struct Tracer {
  const Grid& g;
  const std::vector<int64_t>& corners;  // sorted keys
  const std::vector<double>& value;     // per corner, NaN outside the support
  std::unordered_map<int64_t, int> edge_vertex;
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;

  int64_t offset(int bits) const { return g.key(bits & 1, (bits >> 1) & 1, (bits >> 2) & 1); }
  int corner_index(int64_t key) const {
    const auto it = std::lower_bound(corners.begin(), corners.end(), key);
    return it != corners.end() && *it == key ? int(it - corners.begin()) : -1;
  }
  // The vertex on the edge between corners a and b (a's key the smaller: every edge of the cut
  // runs along a non-negative offset), placed where the values interpolate to zero.
  int vertex(int64_t ka, int64_t kb, double va, double vb) {
    if (ka > kb) std::swap(ka, kb), std::swap(va, vb);
    const int64_t d = kb - ka;
    int bits = 0;
    for (int b = 1; b < 8; ++b)
      if (offset(b) == d) bits = b;
    const auto [it, fresh] = edge_vertex.try_emplace(ka * 8 + bits, int(points.size()));
    if (fresh) {
      const double t = std::clamp(va / (va - vb), 0.01, 0.99);
      points.push_back((1 - t) * g.position(ka) + t * g.position(kb));
    }
    return it->second;
  }
  void triangle(int a, int b, int c, const Eigen::Vector3d& outward) {
    const Eigen::Vector3d n = (points[size_t(b)] - points[size_t(a)]).cross(points[size_t(c)] - points[size_t(a)]);
    if (n.dot(outward) < 0) std::swap(b, c);
    triangles.push_back({a, b, c});
  }
  void tetrahedron(const int64_t key[4], const double v[4]) {
    int inside[4], outside[4], ni = 0, no = 0;
    for (int c = 0; c < 4; ++c) (v[c] < 0 ? inside[ni++] : outside[no++]) = c;
    if (ni == 0 || no == 0) return;
    Eigen::Vector3d outward = Eigen::Vector3d::Zero();
    for (int c = 0; c < no; ++c) outward += g.position(key[outside[c]]) / no;
    for (int c = 0; c < ni; ++c) outward -= g.position(key[inside[c]]) / ni;
    auto at = [&](int a, int b) { return vertex(key[a], key[b], v[a], v[b]); };
    if (ni == 1 || no == 1) {
      const int lone = ni == 1 ? inside[0] : outside[0];
      const int* rest = ni == 1 ? outside : inside;
      triangle(at(lone, rest[0]), at(lone, rest[1]), at(lone, rest[2]), outward);
      return;
    }
    const int q0 = at(inside[0], outside[0]), q1 = at(inside[0], outside[1]), q2 = at(inside[1], outside[1]),
              q3 = at(inside[1], outside[0]);
    triangle(q0, q1, q2, outward);
    triangle(q0, q2, q3, outward);
  }
  void cube(int64_t base) {
    int64_t key[8];
    double v[8];
    for (int b = 0; b < 8; ++b) {
      key[b] = base + offset(b);
      const int i = corner_index(key[b]);
      v[b] = i < 0 ? NAN : value[size_t(i)];
    }
    for (const auto& t : kTets) {
      const int64_t k[4] = {key[t[0]], key[t[1]], key[t[2]], key[t[3]]};
      const double w[4] = {v[t[0]], v[t[1]], v[t[2]], v[t[3]]};
      if (std::isnan(w[0]) || std::isnan(w[1]) || std::isnan(w[2]) || std::isnan(w[3])) continue;
      tetrahedron(k, w);
    }
  }
};

// Drops the triangles with a corner farther than `within` local spacings from its nearest point;
// returns how many.
int keep_near_points(std::vector<std::array<int, 3>>& triangles, const std::vector<Eigen::Vector3d>& points,
                     const PointSetSurface& surface, double within) {
  std::vector<char> near(points.size(), 1);
  parallel_for(int(points.size()), 1024, [&](int i) {
    double d2 = 0;
    const int k = surface.tree().nearest_one(points[size_t(i)], &d2);
    near[size_t(i)] = k >= 0 && std::sqrt(d2) <= within * surface.spacing(k);
  });
  const size_t before = triangles.size();
  triangles.erase(std::remove_if(triangles.begin(), triangles.end(),
                                 [&](const std::array<int, 3>& t) { return !near[size_t(t[0])] || !near[size_t(t[1])] || !near[size_t(t[2])]; }),
                  triangles.end());
  return int(before - triangles.size());
}

}  // namespace

Mesh cloud_surface(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                   const CloudSurfaceOptions& options, CloudSurfaceStats* stats) {
  const Stopwatch clock;
  const PointSetSurface surface(points, normals, options.surface);
  Eigen::Vector3d lo = points[0], hi = points[0];
  for (const auto& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double diag = (hi - lo).norm();
  const double cell = std::max(options.cell_spacing * surface.median_spacing(), diag / std::max(options.max_cells, 8));
  const Grid g = make_grid(points, cell);
  const std::vector<int64_t> cells = active_cells(points, g);
  std::vector<int64_t> corners;
  corners.reserve(cells.size() * 2);
  for (int64_t c : cells)
    for (int b = 0; b < 8; ++b) corners.push_back(c + g.key(b & 1, (b >> 1) & 1, (b >> 2) & 1));
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  std::vector<double> value(corners.size(), NAN);
  parallel_for(int(corners.size()), 2048, [&](int i) {
    const PointSetSurface::Sample s = surface.at(g.position(corners[size_t(i)]));
    if (s.defined) value[size_t(i)] = s.value;
  });
  Tracer tr{g, corners, value, {}, {}, {}};
  for (int64_t c : cells) tr.cube(c);
  parallel_for(int(tr.points.size()), 1024, [&](int i) { tr.points[size_t(i)] = surface.project(tr.points[size_t(i)], options.projections); });
  MeshSoup soup;
  soup.points = std::move(tr.points);
  const int strays = keep_near_points(tr.triangles, soup.points, surface, options.keep_within);
  soup.triangles = std::move(tr.triangles);
  if (soup.triangles.empty())
    throw InputError("no surface could be traced through the points (their normals may all point one way, or the points "
                     "are too sparse for a surface): give the cloud oriented normals");
  const std::vector<std::string> dropped = drop_small_soup_parts(soup, options.min_part);
  LoadOptions lo_options;
  EdgeTable table;
  const LoadReport report = prepare_soup(soup, "the surface of the points", lo_options, &table);
  Mesh mesh = build_mesh(soup, &table);
  if (stats) {
    stats->cell = cell;
    stats->corners = long(corners.size());
    stats->defined = long(std::count_if(value.begin(), value.end(), [](double v) { return !std::isnan(v); }));
    stats->vertices = int(mesh.n_vertices());
    stats->faces = int(mesh.n_faces());
    stats->boundary_loops = report.validation.boundary_loops;
    stats->dropped_parts = int(dropped.size());
    stats->stray_faces = strays;
    stats->seconds = clock.seconds();
  }
  return mesh;
}

}  // namespace sdm
