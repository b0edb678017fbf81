#include "libstm/geometry/local_delaunay.h"

#include "libstm/core/parallel.h"
#include "libstm/geometry/point_kdtree.h"

#include <cmath>

namespace sdm {

namespace {

// A convex polygon around the origin whose edges remember the neighbour that cut them (-1: the box).
struct Cell {
  std::vector<Eigen::Vector2d> corner;
  std::vector<int> edge;  // edge k joins corner k and k + 1, cut by neighbour edge[k]
};

// Clips the cell by the half-plane x . q <= |q|^2 / 2 (closer to the origin than to q).
void clip(Cell& c, const Eigen::Vector2d& q, int id) {
  const double h = 0.5 * q.squaredNorm();
  Cell out;
  const size_t n = c.corner.size();
  for (size_t k = 0; k < n; ++k) {
    const Eigen::Vector2d& a = c.corner[k];
    const Eigen::Vector2d& b = c.corner[(k + 1) % n];
    const double da = a.dot(q) - h, db = b.dot(q) - h;
    if (da <= 0) out.corner.push_back(a), out.edge.push_back(c.edge[k]);
    if ((da <= 0) != (db <= 0)) {
      const Eigen::Vector2d x = a + (b - a) * (da / (da - db));
      out.corner.push_back(x);
      out.edge.push_back(da <= 0 ? id : c.edge[k]);  // leaving: the new edge runs along the cut
    }
  }
  c = std::move(out);
}

}  // namespace

LocalRings local_delaunay_rings(const std::vector<Eigen::Vector3d>& points, int k) {
  const int n = int(points.size());
  const PointKdTree tree(points);
  LocalRings r;
  r.ring.resize(points.size());
  r.triangles.resize(points.size());
  parallel_for(n, 256, [&](int i) {
    const std::vector<int> near = tree.nearest(points[size_t(i)], k + 1);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int j : near) mean += points[size_t(j)];
    mean /= double(near.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (int j : near) cov += (points[size_t(j)] - mean) * (points[size_t(j)] - mean).transpose();
    const Eigen::Matrix3d axes = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors();
    const Eigen::Vector3d u = axes.col(2), v = axes.col(1);
    double reach = 0;
    std::vector<Eigen::Vector2d> q(near.size());
    for (size_t a = 0; a < near.size(); ++a) {
      const Eigen::Vector3d d = points[size_t(near[a])] - points[size_t(i)];
      q[a] = {d.dot(u), d.dot(v)};
      reach = std::max(reach, q[a].norm());
    }
    const double B = 4 * reach + 1e-300;
    Cell c{{{-B, -B}, {B, -B}, {B, B}, {-B, B}}, {-1, -1, -1, -1}};
    for (size_t a = 0; a < near.size(); ++a)
      if (near[a] != i && q[a].squaredNorm() > 0) clip(c, q[a], near[a]);
    auto& ring = r.ring[size_t(i)];
    for (int e : c.edge)
      if (e >= 0 && (ring.empty() || ring.back() != e)) ring.push_back(e);
    if (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
    const size_t m = c.edge.size();
    for (size_t e = 0; e < m; ++e) {
      const int a = c.edge[e], b = c.edge[(e + 1) % m];
      if (a >= 0 && b >= 0 && a != b) r.triangles[size_t(i)].push_back({a, b});
    }
  });
  return r;
}

}  // namespace sdm
